//! Running the binary with a bound on its time: a command that hangs is a
//! failing test, not a test run that never ends. The bounds are generous
//! (many times what the command takes); timing targets live in benchmarks.

use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

/// `command`'s output, or a panic naming `what` once it has run `seconds`
/// (the process is killed first).
pub fn output_within(command: &mut Command, seconds: u64, what: &str) -> Output {
    let mut child = command
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run flipcard");
    // Read the pipes while waiting: a full pipe would stall the child.
    let mut out = child.stdout.take().unwrap();
    let mut err = child.stderr.take().unwrap();
    let read_out = std::thread::spawn(move || {
        let mut v = Vec::new();
        std::io::Read::read_to_end(&mut out, &mut v).map(|_| v)
    });
    let read_err = std::thread::spawn(move || {
        let mut v = Vec::new();
        std::io::Read::read_to_end(&mut err, &mut v).map(|_| v)
    });
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if start.elapsed() > Duration::from_secs(seconds) {
            let _ = child.kill();
            let _ = child.wait();
            panic!("{what} took over {seconds} s");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    Output {
        status,
        stdout: read_out.join().unwrap().unwrap(),
        stderr: read_err.join().unwrap().unwrap(),
    }
}
