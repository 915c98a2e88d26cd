//! Progress on stderr: a bar on a terminal, a line a second otherwise.

use rhonn_app::campaign::Progress;
use std::io::IsTerminal;
use std::sync::Mutex;
use std::time::Instant;

/// Where a campaign's progress goes.
pub enum Reporter {
    Bar(indicatif::ProgressBar),
    Lines(Mutex<Instant>),
}

impl Reporter {
    pub fn new(name: &str) -> Self {
        if std::io::stderr().is_terminal() {
            let bar = indicatif::ProgressBar::new(0);
            bar.set_style(
                indicatif::ProgressStyle::with_template(
                    "{msg} [{bar:40}] {pos}/{len} runs, {per_sec}, ETA {eta}",
                )
                .expect("a valid template")
                .progress_chars("=> "),
            );
            bar.set_message(format!("campaign {name}"));
            Reporter::Bar(bar)
        } else {
            Reporter::Lines(Mutex::new(Instant::now()))
        }
    }

    pub fn update(&self, p: Progress) {
        match self {
            Reporter::Bar(bar) => {
                bar.set_length(p.total as u64);
                bar.set_position(p.done as u64);
                if p.failed > 0 {
                    bar.set_message(format!("campaign {} ({} failed)", p.scenario, p.failed));
                }
            }
            Reporter::Lines(last) => {
                let mut last = last.lock().unwrap_or_else(|e| e.into_inner());
                if last.elapsed().as_secs_f64() >= 1.0 || p.done == p.total {
                    *last = Instant::now();
                    let rate = p.done as f64 / p.elapsed_s.max(1e-9);
                    eprintln!(
                        "campaign {}: {}/{} runs, {} failed, {rate:.1} runs/s, ETA {:.0} s",
                        p.scenario,
                        p.done,
                        p.total,
                        p.failed,
                        (p.total - p.done) as f64 / rate.max(1e-9)
                    );
                }
            }
        }
    }

    pub fn finish(self) {
        if let Reporter::Bar(bar) = self {
            bar.finish();
        }
    }
}

/// A sign of life for a step that may take long (a fit, a prediction): nothing if it ends
/// within a second; after that a spinner with the elapsed time on a terminal, else a line
/// every 5 s. Stops when dropped.
pub struct Busy {
    message: std::sync::Arc<std::sync::Mutex<String>>,
    done: std::sync::Arc<std::sync::atomic::AtomicBool>,
    thread: Option<std::thread::JoinHandle<()>>,
}

impl Busy {
    pub fn start(what: String) -> Busy {
        use std::sync::atomic::Ordering;
        let done = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
        let flag = done.clone();
        let message = std::sync::Arc::new(std::sync::Mutex::new(what));
        let shown = message.clone();
        let current = move || shown.lock().map(|m| m.clone()).unwrap_or_default();
        let thread = std::thread::spawn(move || {
            let start = Instant::now();
            let tick = std::time::Duration::from_millis(50);
            let wait_until = |secs: f64| {
                while start.elapsed().as_secs_f64() < secs {
                    if flag.load(Ordering::Relaxed) {
                        return false;
                    }
                    std::thread::sleep(tick);
                }
                true
            };
            if !wait_until(1.0) {
                return;
            }
            if std::io::stderr().is_terminal() {
                let bar = indicatif::ProgressBar::new_spinner();
                bar.set_style(
                    indicatif::ProgressStyle::with_template("{spinner} {msg} ({elapsed})")
                        .expect("a valid template"),
                );
                bar.set_message(current());
                bar.enable_steady_tick(std::time::Duration::from_millis(100));
                while !flag.load(Ordering::Relaxed) {
                    bar.set_message(current());
                    std::thread::sleep(tick);
                }
                bar.finish_and_clear();
            } else {
                let mut next = 1.0;
                while wait_until(next) {
                    eprintln!("{}: {:.0} s so far", current(), start.elapsed().as_secs_f64());
                    next += 5.0;
                }
            }
        });
        Busy {
            message,
            done,
            thread: Some(thread),
        }
    }
}

impl Busy {
    /// Replace the message shown.
    pub fn set_message(&self, m: String) {
        if let Ok(mut g) = self.message.lock() {
            *g = m;
        }
    }
}

impl Drop for Busy {
    fn drop(&mut self) {
        self.done.store(true, std::sync::atomic::Ordering::Relaxed);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}
