//! Cooperative cancellation of long library calls: a door that can be interrupted
//! (Python's Ctrl-C) calls [`request`]; the long loops (the selection's folds, the
//! Levenberg-Marquardt iterations, a campaign's runs) ask [`requested`] at each step and
//! stop, and the call returns [`crate::Error::Interrupted`]. One flag for the process, as
//! Ctrl-C is one signal for it: a [`Worker`] starting clears it, once the calls it stopped
//! have wound down (so that a new call neither inherits the stop nor revives them).

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

static REQUESTED: AtomicBool = AtomicBool::new(false);
/// Workers running.
static LIVE: AtomicUsize = AtomicUsize::new(0);

/// Counts a worker as running while it lives (a panic included).
struct Live;

impl Live {
    fn new() -> Live {
        LIVE.fetch_add(1, Ordering::SeqCst);
        Live
    }
}

impl Drop for Live {
    fn drop(&mut self) {
        LIVE.fetch_sub(1, Ordering::SeqCst);
    }
}

/// Ask every running call to stop at its next check.
pub fn request() {
    REQUESTED.store(true, Ordering::Relaxed);
}

/// Forget an earlier request (a new call starts).
pub fn clear() {
    REQUESTED.store(false, Ordering::Relaxed);
}

/// Whether a stop was asked for.
pub fn requested() -> bool {
    REQUESTED.load(Ordering::Relaxed)
}

/// [`crate::Error::Interrupted`] when a stop was asked for.
pub fn check() -> crate::Result<()> {
    if requested() {
        Err(crate::Error::Interrupted)
    } else {
        Ok(())
    }
}

/// A long call on a worker thread, which its caller (a door that can be interrupted)
/// waits for in short steps, looking for an interrupt between them.
pub struct Worker<T>(std::sync::Mutex<std::sync::mpsc::Receiver<T>>);

/// What a wait found.
pub enum Waited<T> {
    /// The call's result.
    Done(T),
    /// Still running.
    Running,
    /// The worker ended without a result (it panicked).
    Lost,
}

impl<T: Send + 'static> Worker<T> {
    /// Start `f` on its own thread. Workers stopped by an earlier request are waited for
    /// first (each stops at its next check), then the request is forgotten ([`clear`]).
    pub fn start(f: impl FnOnce() -> T + Send + 'static) -> Self {
        while requested() && LIVE.load(Ordering::SeqCst) > 0 {
            std::thread::sleep(std::time::Duration::from_millis(5));
        }
        clear();
        let live = Live::new();
        let (tx, rx) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            let _live = live;
            tx.send(f())
        });
        Worker(std::sync::Mutex::new(rx))
    }

    /// Wait for the result at most `timeout`.
    pub fn wait(&self, timeout: std::time::Duration) -> Waited<T> {
        let rx = self.0.lock().unwrap_or_else(|e| e.into_inner());
        match rx.recv_timeout(timeout) {
            Ok(v) => Waited::Done(v),
            Err(std::sync::mpsc::RecvTimeoutError::Timeout) => Waited::Running,
            Err(std::sync::mpsc::RecvTimeoutError::Disconnected) => Waited::Lost,
        }
    }
}
