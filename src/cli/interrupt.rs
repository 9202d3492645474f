//! Ctrl-C and SIGTERM during `drillopt simulate`: the first ends the run after the step in
//! progress, so that what was computed is written (the time series renamed into place, the
//! summary marked `interrupted`, the plots), instead of the process dying with its time series
//! in a hidden temporary file and no summary; a second one ends the process at once (the
//! default action is back after the first).
//!
//! The handler only stores an atomic flag and resets the two signals' actions, which is
//! async-signal-safe (POSIX lists `signal`); the run polls the flag once per step
//! ([`crate::sim::StopFlag`]).

use crate::sim::StopFlag;
use std::sync::atomic::{AtomicBool, Ordering};

/// Raised by the first SIGINT or SIGTERM after [`install`].
static RAISED: AtomicBool = AtomicBool::new(false);

#[cfg(unix)]
extern "C" fn on_signal(_: libc::c_int) {
    RAISED.store(true, Ordering::Relaxed);
    // SAFETY: `signal` is async-signal-safe; SIG_DFL is a valid action.
    unsafe {
        libc::signal(libc::SIGINT, libc::SIG_DFL);
        libc::signal(libc::SIGTERM, libc::SIG_DFL);
    }
}

/// Catch SIGINT and SIGTERM until [`uninstall`]; the flag a run polls.
pub fn install() -> StopFlag {
    RAISED.store(false, Ordering::Relaxed);
    #[cfg(unix)]
    // SAFETY: the handler only touches an atomic and resets the actions (see the module doc).
    unsafe {
        let handler = on_signal as extern "C" fn(libc::c_int) as libc::sighandler_t;
        libc::signal(libc::SIGINT, handler);
        libc::signal(libc::SIGTERM, handler);
    }
    StopFlag(Some(&RAISED))
}

/// Give SIGINT and SIGTERM their default actions back.
pub fn uninstall() {
    #[cfg(unix)]
    // SAFETY: SIG_DFL is a valid action.
    unsafe {
        libc::signal(libc::SIGINT, libc::SIG_DFL);
        libc::signal(libc::SIGTERM, libc::SIG_DFL);
    }
}
