//! What the benches share: how much to measure (the full bench under `cargo bench`, or its
//! smoke run under `cargo test`), and the A-against-B harness whose figure is the median and
//! quartiles of per-round ratios from interleaved rounds, with the machine's load beside it;
//! and instruction counts by callgrind, of the bench run again in a child process.

/// How much to measure: the full bench, or one small round of everything (the tests' run).
#[derive(Clone, Copy, PartialEq)]
pub enum Size {
    Full,
    Smoke,
}

impl Size {
    /// `cargo bench` passes `--bench` to a bench binary; `cargo test` runs the same binary
    /// without it (every bench is `test = true`), which makes that its smoke run: a stale
    /// bench fails the test suite, not a reader.
    pub fn from_args() -> Size {
        if std::env::args().any(|a| a == "--bench") {
            Size::Full
        } else {
            Size::Smoke
        }
    }

    /// `full` for the bench, `smoke` for its run in the tests.
    pub fn pick<T>(self, full: T, smoke: T) -> T {
        if self == Size::Full {
            full
        } else {
            smoke
        }
    }
}

/// Median and quartiles of a list: (first quartile, median, third quartile).
pub fn quartiles(mut v: Vec<f64>) -> (f64, f64, f64) {
    v.sort_by(f64::total_cmp);
    let at = |q: f64| v[((v.len() - 1) as f64 * q).round() as usize];
    (at(0.25), at(0.5), at(0.75))
}

/// The host's load when a figure was taken (1, 5 and 15-minute averages and the cores), so a
/// reader can tell a busy machine's figure from a quiet one's.
pub fn load_line() -> String {
    let cores = std::thread::available_parallelism().map_or(0, |n| n.get());
    match std::fs::read_to_string("/proc/loadavg") {
        Ok(l) => format!(
            "load average {} on {cores} cores",
            l.split_whitespace().take(3).collect::<Vec<_>>().join(" ")
        ),
        Err(_) => format!("load average not readable here ({cores} cores)"),
    }
}

/// Each side's measurements, one per round, taken in interleaved rounds.
pub struct Paired {
    pub a: Vec<f64>,
    pub b: Vec<f64>,
}

/// `rounds` rounds of A and B, the order alternating from round to round (so that whatever
/// the first side leaves warm or cold favours neither): the machine's drift over the run hits
/// both sides of a round alike, and their ratio cancels it.
pub fn interleaved(rounds: usize, mut a: impl FnMut() -> f64, mut b: impl FnMut() -> f64) -> Paired {
    let mut p = Paired { a: vec![], b: vec![] };
    for round in 0..rounds {
        if round % 2 == 0 {
            p.a.push(a());
            p.b.push(b());
        } else {
            p.b.push(b());
            p.a.push(a());
        }
    }
    p
}

impl Paired {
    /// B / A per round: (first quartile, median, third quartile).
    pub fn ratio(&self) -> (f64, f64, f64) {
        quartiles(self.a.iter().zip(&self.b).map(|(a, b)| b / a).collect())
    }

    /// Both sides' medians and the per-round ratio, as lines a bench prints.
    pub fn report(&self, (name_a, name_b): (&str, &str), unit: &str) -> String {
        let side = |name: &str, v: &[f64]| {
            let (q1, m, q3) = quartiles(v.to_vec());
            format!("  {name:<38} {m:>10.3} {unit} (quartiles {q1:.3}–{q3:.3})")
        };
        let (q1, m, q3) = self.ratio();
        format!(
            "{}\n{}\n  ratio {name_b} / {name_a}: {m:.3}× per round (quartiles {q1:.3}–{q3:.3}, {} interleaved rounds; {})",
            side(name_a, &self.a),
            side(name_b, &self.b),
            self.a.len(),
            load_line()
        )
    }
}

/// Milliseconds `f` takes.
pub fn ms(f: impl FnOnce()) -> f64 {
    let t = std::time::Instant::now();
    f();
    t.elapsed().as_secs_f64() * 1e3
}

/// Instructions callgrind counts in a child process running this bench with `env` set (which
/// puts it in the mode to be counted); with `inside`, only those executed within the
/// functions it names (callgrind's `--toggle-collect`).
pub fn count_self(env: &[(&str, String)], inside: Option<&str>) -> Result<u64, String> {
    let out = std::process::Command::new("valgrind")
        .args(["--tool=callgrind", "--callgrind-out-file=/dev/null"])
        .args(inside.map(|f| format!("--toggle-collect={f}")))
        .arg(std::env::current_exe().map_err(|e| e.to_string())?)
        .envs(env.iter().map(|(k, v)| (k, v)))
        .output()
        .map_err(|e| format!("valgrind: {e}"))?;
    let text = String::from_utf8_lossy(&out.stderr);
    text.lines()
        .find_map(|l| l.split("Collected :").nth(1))
        .and_then(|n| n.trim().parse().ok())
        .ok_or_else(|| format!("no count in callgrind's output ({})", out.status))
}
