//! `rhonn identify --stream` and `--follow FILE`: the command's side of a live stream —
//! standard input or a file that grows, and Ctrl-C, which ends the stream as the end of
//! the input does (the model learned so far is frozen and written).

use anyhow::Result;
use rhonn_app as commands;
use std::io::{BufRead, BufReader, Read, Write};
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};

/// Set by the SIGINT handler.
static INTERRUPTED: AtomicBool = AtomicBool::new(false);

/// Ctrl-C ends the stream instead of the process. Written by hand on `libc::signal` (the
/// `ctrlc` crate does the same, and is not among this project's dependencies): the
/// handler only stores to an atomic, which is async-signal-safe.
#[cfg(unix)]
fn catch_interrupt() {
    extern "C" fn on_sigint(_: libc::c_int) {
        INTERRUPTED.store(true, Ordering::SeqCst);
    }
    // SAFETY: installs a handler that only stores to a static atomic.
    unsafe {
        libc::signal(
            libc::SIGINT,
            on_sigint as extern "C" fn(libc::c_int) as libc::sighandler_t,
        );
    }
}

#[cfg(not(unix))]
fn catch_interrupt() {}

/// A file read as it grows: at its end, wait and read again, until Ctrl-C.
struct Follow {
    file: std::fs::File,
}

impl Read for Follow {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        loop {
            let n = self.file.read(buf)?;
            if n > 0 || INTERRUPTED.load(Ordering::SeqCst) {
                return Ok(n);
            }
            std::thread::sleep(std::time::Duration::from_millis(100));
        }
    }
}

/// Learn the stream of `req` from standard input, or from `follow` as it grows; print each
/// line as it comes; write the folder; fail (after writing) when a malformed line stopped it.
pub fn identify(req: &commands::StreamRequest, follow: Option<&Path>) -> Result<()> {
    catch_interrupt();
    let mut input: Box<dyn BufRead> = match follow {
        Some(p) => {
            let file = std::fs::File::open(p).map_err(|e| anyhow::anyhow!("{}: {e}", p.display()))?;
            Box::new(BufReader::new(Follow { file }))
        }
        None => Box::new(std::io::stdin().lock()),
    };
    let stdout = std::io::stdout();
    let mut out = stdout.lock();
    let mut print = |line: &str| {
        // A closed pipe (`| head`) ends the printing, not the learning.
        let _ = writeln!(out, "{line}");
    };
    let stop = || INTERRUPTED.load(Ordering::SeqCst);
    let mut warn = |line: &str| eprintln!("{line}");
    let (o, stopped) = commands::identify_stream(req, &mut input, &mut print, &mut warn, &stop)?;
    o.print_to(&mut |l| eprintln!("{l}"));
    match stopped {
        Some(e) => Err(anyhow::anyhow!(
            "{e}; the stream stopped there (--on-error stop) and the model learned until then was written"
        )),
        None => Ok(()),
    }
}
