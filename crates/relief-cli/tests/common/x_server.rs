//! A virtual X server (Xvfb) for tests that open relief's window: one per use, started on a
//! free display and stopped afterwards, so that tests may run side by side.

use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Stdio};

/// A running Xvfb, stopped when dropped.
pub struct XServer {
    child: Child,
    /// The display to connect to, e.g. ":1".
    pub display: String,
}

impl Drop for XServer {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Starts Xvfb on a display it picks itself (`-displayfd`). `None`, after saying so, where
/// Xvfb is not installed and RELIEF_REQUIRE_CLIENTS is not 1 (.ci/run installs it and sets it).
pub fn x_server() -> Option<XServer> {
    let spawned = Command::new("Xvfb")
        .args(["-displayfd", "1", "-screen", "0", "1920x1080x24", "-nolisten", "tcp"])
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn();
    let mut child = match spawned {
        Ok(child) => child,
        Err(e) => {
            assert!(
                std::env::var("RELIEF_REQUIRE_CLIENTS").as_deref() != Ok("1"),
                "Xvfb is required (RELIEF_REQUIRE_CLIENTS=1; .ci/run installs it): {e}"
            );
            println!("skipped: Xvfb cannot be started ({e}); apt-get install xvfb");
            return None;
        }
    };
    // Xvfb writes its display number once it accepts connections.
    let mut line = String::new();
    let read = BufReader::new(child.stdout.take().unwrap()).read_line(&mut line);
    let number = line.trim();
    assert!(
        read.is_ok() && !number.is_empty() && number.chars().all(|c| c.is_ascii_digit()),
        "Xvfb did not report a display: {line:?}"
    );
    Some(XServer { display: format!(":{number}"), child })
}
