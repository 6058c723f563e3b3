//! Clean exit on SIGINT, SIGTERM and SIGHUP: the temporary files of writes in flight
//! ([`mrbrake::report::atomic`]) are removed, then the process dies of the same signal (so a shell or
//! a batch system sees the usual "killed by SIGTERM" status).
//!
//! The handler itself only wakes a watcher thread (signal-hook's self-pipe); the file removal runs
//! on that thread, where locking and system calls are allowed. A results store needs no cleanup: its
//! committed transactions are on disk and SQLite rolls back an unfinished one on the next open.

/// Installs the handlers (once, at start-up). Failing to install them is not fatal: outputs stay
/// atomic, only a stray temporary file may be left behind on a signal.
#[cfg(unix)]
pub fn install() {
    use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
    let Ok(mut signals) = signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP]) else {
        return;
    };
    let watcher = std::thread::Builder::new().name("signals".into()).spawn(move || {
        if let Some(signal) = signals.forever().next() {
            mrbrake::report::atomic::remove_pending_temp_files();
            // Restores the default action and raises the signal again.
            let _ = signal_hook::low_level::emulate_default_handler(signal);
            std::process::exit(128 + signal);
        }
    });
    drop(watcher);
}

/// No signal handling outside Unix: outputs stay atomic, a stray temporary file may remain.
#[cfg(not(unix))]
pub fn install() {}
