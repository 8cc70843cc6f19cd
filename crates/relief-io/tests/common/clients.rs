//! The real clients some tests need (GDAL through rasterio, rio-cogeo's COG validator, Pillow,
//! NumPy, trimesh, the Khronos glTF validator, Xvfb, xdotool), and the test harness that reports a test whose client is
//! missing as ignored, with the reason and the install command, instead of passing it; and
//! likewise a test that reads the shared data (../shared) in a bare clone.
//!
//! Shared by the test targets of relief-io, relief-cli and relief-mesh that need a client
//! (included by path, as `shared_data.rs` is). Each such target has `harness = false` in its
//! crate's Cargo.toml and a `main` that lists its tests with the clients each needs:
//!
//! ```ignore
//! fn main() {
//!     clients::run(vec![
//!         clients::trial!(reads_back_with_gdal, Rasterio),
//!         clients::trial!(needs_no_client),
//!     ]);
//! }
//! ```
//!
//! Each client is probed once per test process, when a test first needs it. Where one is
//! missing, the test is reported `ignored (client missing: ...)`; with
//! RELIEF_REQUIRE_CLIENTS=1 (.ci/run sets it and installs the clients) it fails instead.
//!
//! To move a file of plain `#[test]`s that need a client here: add `[[test]] name = "FILE"
//! harness = false` to its crate's Cargo.toml (and `libtest-mimic.workspace = true` to its
//! dev-dependencies if it lacks it); in the file, delete each `#[test]` line and add the `main`
//! above listing every test with the clients it needs (a test left out is dead code, which
//! Clippy refuses); make the skip branches of the helpers hard expectations
//! (`python(..).unwrap()`, `x_server().expect(..)`), since a listed test only runs where its
//! clients are; split a test that needs a client for only part of its checks. A crate without
//! `tests/common` includes this file by `#[path]` as `mod clients;`.

// Each test target uses a part of it.
#![allow(dead_code)]

use libtest_mimic::{Arguments, Completion, Failed, Trial};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::OnceLock;

/// What starts the reason of a test ignored for a missing client; `.ci/run` counts these.
pub const MISSING: &str = "client missing";

/// What starts the reason of a test ignored for want of the shared data; `.ci/run` counts these.
pub const SHARED_MISSING: &str = "shared data missing";

/// A program or library outside the workspace that a test runs to check relief's output.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Client {
    /// GDAL's Python binding, rasterio.
    Rasterio,
    /// rio-cogeo, whose `cog_validate` checks a cloud-optimised GeoTIFF as GDAL's validator.
    RioCogeo,
    /// Pillow (`import PIL`).
    Pillow,
    /// NumPy.
    Numpy,
    /// trimesh, a Python mesh library.
    Trimesh,
    /// The Khronos glTF validator (npm `gltf-validator` in tools/gltf-validator, run by node).
    GltfValidator,
    /// Xvfb, a virtual X server.
    Xvfb,
    /// xdotool, which types keys and moves the mouse in an X window.
    Xdotool,
}

const ALL: [Client; 8] = [
    Client::Rasterio,
    Client::RioCogeo,
    Client::Pillow,
    Client::Numpy,
    Client::Trimesh,
    Client::GltfValidator,
    Client::Xvfb,
    Client::Xdotool,
];

impl Client {
    /// What is missing when the probe fails, and how to install it.
    pub fn missing(self) -> String {
        let python = |module: &str, package: &str| {
            format!("python3 cannot import {module}, install: pip install {package}")
        };
        match self {
            Client::Rasterio => python("rasterio", "rasterio"),
            Client::RioCogeo => python("rio_cogeo", "rio-cogeo"),
            Client::Pillow => python("PIL", "pillow"),
            Client::Numpy => python("numpy", "numpy"),
            Client::Trimesh => python("trimesh", "trimesh"),
            Client::GltfValidator => "node or the glTF validator is not installed, install: \
                 apt-get install nodejs npm && npm ci --prefix tools/gltf-validator"
                .to_string(),
            Client::Xvfb => "Xvfb is not on PATH, install: apt-get install xvfb".to_string(),
            Client::Xdotool => {
                "xdotool is not on PATH, install: apt-get install xdotool".to_string()
            }
        }
    }

    /// Whether the client is there; probed once per process.
    pub fn present(self) -> bool {
        static PROBED: [OnceLock<bool>; ALL.len()] = [const { OnceLock::new() }; ALL.len()];
        let index = ALL.iter().position(|&c| c == self).unwrap();
        *PROBED[index].get_or_init(|| self.probe())
    }

    fn probe(self) -> bool {
        let imports = |module: &str| {
            Command::new("python3")
                .args(["-c", &format!("import {module}")])
                .stdout(Stdio::null())
                .stderr(Stdio::null())
                .status()
                .is_ok_and(|s| s.success())
        };
        match self {
            Client::Rasterio => imports("rasterio"),
            Client::RioCogeo => imports("rio_cogeo"),
            Client::Pillow => imports("PIL"),
            Client::Numpy => imports("numpy"),
            Client::Trimesh => imports("trimesh"),
            Client::GltfValidator => {
                // As validate_gltf.mjs finds it.
                let dir = std::env::var_os("RELIEF_GLTF_VALIDATOR_DIR")
                    .map(PathBuf::from)
                    .unwrap_or_else(|| repository().join("tools/gltf-validator"));
                on_path("node") && dir.join("node_modules/gltf-validator/package.json").is_file()
            }
            Client::Xvfb => on_path("Xvfb"),
            Client::Xdotool => on_path("xdotool"),
        }
    }
}

/// The repository's root (every crate is `crates/NAME`).
fn repository() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Whether an executable file named `program` is in a folder of PATH.
fn on_path(program: &str) -> bool {
    use std::os::unix::fs::PermissionsExt;
    let Some(path) = std::env::var_os("PATH") else { return false };
    std::env::split_paths(&path).any(|dir| {
        std::fs::metadata(dir.join(program))
            .is_ok_and(|m| m.is_file() && m.permissions().mode() & 0o111 != 0)
    })
}

/// Whether a missing client fails a test rather than having it ignored (.ci/run sets it).
pub fn required() -> bool {
    std::env::var("RELIEF_REQUIRE_CLIENTS").as_deref() == Ok("1")
}

/// The test `name` running `test` (which fails by panicking) where every client of `needs` is
/// present; else ignored, with the reason and the install commands, or with
/// RELIEF_REQUIRE_CLIENTS=1 failed. Prefer the [`trial!`] macro, which names it after `test`.
pub fn trial_needing(name: &str, needs: &[Client], test: fn()) -> Trial {
    let needs = needs.to_vec();
    Trial::ignorable_test(name, move || {
        let missing: Vec<String> =
            needs.iter().filter(|c| !c.present()).map(|c| c.missing()).collect();
        if missing.is_empty() {
            test();
            return Ok(Completion::Completed);
        }
        let reason = format!("{MISSING}: {}", missing.join("; "));
        if required() {
            return Err(Failed::from(format!(
                "{reason}; required by RELIEF_REQUIRE_CLIENTS=1 (.ci/run installs it)"
            )));
        }
        Ok(Completion::ignored_with(reason))
    })
}

/// `trial!(test_fn, Client, ...)`: the [`trial_needing`] named after the function, needing those
/// clients (none for a test that needs no client). `clients` must name this module.
#[allow(unused_macros)]
macro_rules! trial {
    ($test:ident $(, $client:ident)* $(,)?) => {
        clients::trial_needing(stringify!($test), &[$(clients::Client::$client),*], $test)
    };
}
#[allow(unused_imports)]
pub(crate) use trial;

/// The test `name` running `test`, which reads `relative` (say `data/jacksboro_fault_dem.npy`)
/// from the project's shared folder with `shared_data`: ignored, with the reason, where that
/// file and the folder, ../shared beside the repository, are absent (a bare clone) and
/// RELIEF_REQUIRE_SHARED_DATA is not 1. Elsewhere it runs, and `shared_data` fails it if the
/// file is missing. Prefer the [`trial_reading!`] macro, which names it after `test`.
pub fn trial_reading_shared_data(name: &str, relative: &'static str, test: fn()) -> Trial {
    Trial::ignorable_test(name, move || {
        // Where shared_data.rs looks.
        let shared = repository().join("../shared");
        let required = std::env::var("RELIEF_REQUIRE_SHARED_DATA").as_deref() == Ok("1");
        if !shared.join(relative).is_file() && !shared.is_dir() && !required {
            return Ok(Completion::ignored_with(format!(
                "{SHARED_MISSING}: ../shared, which holds {relative}, is not beside the \
                 repository"
            )));
        }
        test();
        Ok(Completion::Completed)
    })
}

/// `trial_reading!(test_fn, "data/FILE")`: the [`trial_reading_shared_data`] named after the
/// function.
#[allow(unused_macros)]
macro_rules! trial_reading {
    ($test:ident, $relative:expr $(,)?) => {
        clients::trial_reading_shared_data(stringify!($test), $relative, $test)
    };
}
#[allow(unused_imports)]
pub(crate) use trial_reading;

/// Runs `trials` as libtest does (same options and output: `cargo test -- FILTER` works, and
/// RUST_TEST_THREADS too) and exits with its code.
pub fn run(trials: Vec<Trial>) -> ! {
    let mut args = Arguments::from_args();
    if args.test_threads.is_none() {
        args.test_threads = std::env::var("RUST_TEST_THREADS").ok().and_then(|n| n.parse().ok());
    }
    libtest_mimic::run(&args, trials).exit()
}

/// A test of this accounting: reruns this test binary on `name` (a test that needs `client`)
/// with a PATH where `client` is missing (only a `python3` that can import nothing, no node,
/// no Xvfb, no xdotool), and checks that the test is reported ignored with the reason, and
/// that with RELIEF_REQUIRE_CLIENTS=1 it fails, saying why.
pub fn accounting_trial(name: &'static str, client: Client) -> Trial {
    Trial::test(format!("a_missing_client_ignores_{name}"), move || {
        let stub =
            std::env::temp_dir().join(format!("relief-clients-stub-{name}-{}", std::process::id()));
        std::fs::create_dir_all(&stub).unwrap();
        let python3 = stub.join("python3");
        std::fs::write(&python3, "#!/bin/sh\nexit 1\n").unwrap();
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&python3, std::fs::Permissions::from_mode(0o755)).unwrap();
        let run = |require: &str| {
            let out = Command::new(std::env::current_exe().unwrap())
                .args([name, "--exact", "--test-threads", "1", "--color", "never"])
                .env("PATH", &stub)
                .env("RELIEF_REQUIRE_CLIENTS", require)
                .env_remove("RELIEF_GLTF_VALIDATOR_DIR")
                .output()
                .unwrap();
            (out.status.success(), String::from_utf8_lossy(&out.stdout).into_owned())
        };
        let (ok, text) = run("0");
        let reason = format!("{MISSING}: {}", client.missing());
        let line = format!("test {name} ... ignored ({reason})");
        if !ok || !text.contains(&line) || !text.contains("0 passed; 0 failed; 1 ignored") {
            return Err(format!("expected `{line}` and 1 ignored, got:\n{text}").into());
        }
        let (ok, text) = run("1");
        let failed = text.contains(&format!("test {name} ... FAILED"))
            && text.contains(&reason)
            && text.contains("0 passed; 1 failed; 0 ignored");
        let _ = std::fs::remove_dir_all(&stub);
        if ok || !failed {
            return Err(format!("with RELIEF_REQUIRE_CLIENTS=1 {name} should fail:\n{text}").into());
        }
        Ok(())
    })
}
