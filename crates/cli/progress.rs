//! Progress on stderr: a bar on a terminal, a line a second otherwise.

use rhonn_report::campaign::Progress;
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
