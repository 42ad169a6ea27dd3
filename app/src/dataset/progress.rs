//! Progress of a dataset on standard error: a bar with rate and ETA redrawn in place on a
//! terminal, a plain line every few seconds otherwise (logs of batch jobs stay readable).

use std::io::{IsTerminal, Write};
use std::time::{Duration, Instant};

pub(super) struct Progress {
    total: usize,
    done: usize,
    failed: usize,
    started: Instant,
    last: Instant,
    tty: bool,
}

const PLAIN_EVERY: Duration = Duration::from_secs(5);
const REDRAW_EVERY: Duration = Duration::from_millis(100);

impl Progress {
    pub(super) fn new(total: usize, skipped: usize) -> Self {
        if skipped > 0 {
            eprintln!("{skipped} complete world(s) already there: kept");
        }
        let now = Instant::now();
        let p = Progress {
            total,
            done: 0,
            failed: 0,
            started: now,
            last: now,
            tty: std::io::stderr().is_terminal(),
        };
        if p.tty && total > 0 {
            p.draw("starting");
        }
        p
    }

    pub(super) fn finished(&mut self, name: &str, ok: bool) {
        self.done += 1;
        self.failed += usize::from(!ok);
        let now = Instant::now();
        if self.tty {
            if now - self.last >= REDRAW_EVERY || self.done == self.total {
                self.last = now;
                self.draw(name);
            }
        } else if now - self.last >= PLAIN_EVERY || self.done == self.total {
            self.last = now;
            eprintln!("{}", self.line(name));
        }
    }

    fn line(&self, name: &str) -> String {
        let elapsed = self.started.elapsed().as_secs_f64();
        let rate = self.done as f64 / elapsed.max(1e-9);
        let left = (self.total - self.done) as f64 / rate.max(1e-9);
        let failed = if self.failed > 0 {
            format!(", {} failed", self.failed)
        } else {
            String::new()
        };
        format!(
            "{}/{} worlds ({name}){failed}, {rate:.1}/s, elapsed {}, ETA {}",
            self.done,
            self.total,
            clock(elapsed),
            if self.done == 0 {
                "-".into()
            } else {
                clock(left)
            }
        )
    }

    fn draw(&self, name: &str) {
        const WIDTH: usize = 30;
        let filled = WIDTH * self.done / self.total.max(1);
        let bar = format!("[{}{}]", "#".repeat(filled), ".".repeat(WIDTH - filled));
        let mut err = std::io::stderr().lock();
        let _ = write!(err, "\r\x1b[2K{bar} {}", self.line(name));
        let _ = err.flush();
    }

    pub(super) fn close(self) {
        if self.tty && self.total > 0 {
            eprintln!();
        }
    }
}

/// `1h02m03s`, `2m05s`, `7s`.
fn clock(seconds: f64) -> String {
    let s = seconds.round() as u64;
    match (s / 3600, s / 60 % 60, s % 60) {
        (0, 0, s) => format!("{s}s"),
        (0, m, s) => format!("{m}m{s:02}s"),
        (h, m, s) => format!("{h}h{m:02}m{s:02}s"),
    }
}
