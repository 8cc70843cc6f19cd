//! Running the real clients of relief's formats (GDAL through rasterio, Pillow, NumPy) from
//! the tests; shared by relief-io's and relief-cli's tests.

/// Runs a Python snippet with the real client of a format (e.g. `rasterio`, GDAL's Python
/// binding) and returns what it printed; `None` (after saying so) when python3 cannot import
/// `module` and RELIEF_REQUIRE_CLIENTS is not 1 (.ci/run sets it and installs the clients).
/// A script that fails fails the test, with its error output. A test run by the clients
/// harness (`clients.rs`, `clients::trial!(test, Rasterio)`) is ignored, with the reason,
/// before it gets here without the module, so it never sees `None`.
pub fn python(module: &str, script: &str) -> Option<String> {
    use std::process::Command;
    let probe = Command::new("python3").args(["-c", &format!("import {module}")]).output();
    if !probe.is_ok_and(|o| o.status.success()) {
        assert!(
            std::env::var("RELIEF_REQUIRE_CLIENTS").as_deref() != Ok("1"),
            "python3 with {module} is required (RELIEF_REQUIRE_CLIENTS=1); .ci/run installs it"
        );
        println!("skipped: python3 cannot import {module}");
        return None;
    }
    let out = Command::new("python3").args(["-c", script]).output().unwrap();
    assert!(out.status.success(), "{script}\n{}", String::from_utf8_lossy(&out.stderr));
    Some(String::from_utf8_lossy(&out.stdout).trim().to_string())
}
