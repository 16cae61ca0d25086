//! Writing to a closed pipe ends the process quietly (the conventional SIGPIPE death, shell
//! status 141), never with a panic.

#[cfg(unix)]
#[test]
fn a_reader_that_goes_away_ends_the_command_without_a_panic() {
    use std::os::unix::process::ExitStatusExt;
    use std::process::{Command, Stdio};
    for args in [&["schema", "environment"][..], &["schema", "knowledge"][..]] {
        let mut child = Command::new(env!("CARGO_BIN_EXE_avs"))
            .args(args)
            .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("the avs binary runs");
        // Close the read end before the child writes: every write then hits a closed pipe.
        drop(child.stdout.take());
        let out = child.wait_with_output().expect("the child ends");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!stderr.contains("panicked"), "avs {args:?}: {stderr}");
        assert!(
            out.status.success() || out.status.signal() == Some(libc_sigpipe()),
            "avs {args:?}: {:?}, stderr: {stderr}",
            out.status
        );
    }
}

/// SIGPIPE's number on Linux and the BSDs.
#[cfg(unix)]
fn libc_sigpipe() -> i32 {
    13
}
