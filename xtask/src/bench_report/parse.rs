//! Reading what a bench run printed: the bench firmware's UART lines and the
//! output of the two simavr tests `scripts/bench.sh` runs for the display and
//! the product's stack.

/// One timed routine: a `B <name> <median> <min> <max> <stack>` line.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Routine {
    /// The routine's name as the bench prints it.
    pub name: String,
    /// Cycles (stamp overhead subtracted).
    pub median: u64,
    /// Fastest run, cycles.
    pub min: u64,
    /// Slowest run, cycles.
    pub max: u64,
    /// Stack high-water mark while it ran, bytes.
    pub stack: u64,
}

/// One counted quantity: an `I <name> <median> <min> <max>` line.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Count {
    /// The quantity's name as the bench prints it.
    pub name: String,
    /// Median of the runs.
    pub median: u64,
    /// Smallest.
    pub min: u64,
    /// Largest.
    pub max: u64,
}

/// The bench firmware's output (`avr-run bench.elf`), cleaned line by line:
/// terminal colour codes removed, surrounding blanks and trailing dots (the
/// harness's progress marks) trimmed, empty lines dropped.
#[derive(Debug, Clone, Default)]
pub struct BenchOutput {
    lines: Vec<String>,
}

impl BenchOutput {
    /// Keeps the bench firmware's output lines for the lookups below.
    pub fn parse(text: &str) -> BenchOutput {
        let lines = text
            .lines()
            .map(|l| strip_ansi(l).trim().trim_end_matches('.').trim().to_string())
            .filter(|l| !l.is_empty())
            .collect();
        BenchOutput { lines }
    }

    /// The numbers of every line tagged `tag` (the tag's own word left out).
    pub fn rows(&self, tag: &str) -> Result<Vec<Vec<u64>>, String> {
        self.lines
            .iter()
            .filter(|l| l.split_whitespace().next() == Some(tag))
            .map(|l| l.split_whitespace().skip(1).map(|w| number(w, l)).collect())
            .collect()
    }

    /// The timed routines in the order the bench ran them.
    pub fn routines(&self) -> Result<Vec<Routine>, String> {
        self.named("B", 4)?
            .into_iter()
            .map(|(name, v)| Ok(Routine { name, median: v[0], min: v[1], max: v[2], stack: v[3] }))
            .collect()
    }

    /// The counted quantities in the order the bench printed them.
    pub fn counts(&self) -> Result<Vec<Count>, String> {
        self.named("I", 3)?
            .into_iter()
            .map(|(name, v)| Ok(Count { name, median: v[0], min: v[1], max: v[2] }))
            .collect()
    }

    /// The cycles of one empty timed section (`O <cycles>`), subtracted from
    /// every figure.
    pub fn stamp_overhead(&self) -> Result<u64, String> {
        self.first("O", 1).map(|v| v[0])
    }

    /// The bench's own stack: (high-water mark, bytes never touched), `S`.
    pub fn stack(&self) -> Result<(u64, u64), String> {
        self.first("S", 2).map(|v| (v[0], v[1]))
    }

    /// `<tag> <name> <n numbers>` lines; others with that tag are not rows of
    /// this kind and are skipped.
    fn named(&self, tag: &str, n: usize) -> Result<Vec<(String, Vec<u64>)>, String> {
        self.lines
            .iter()
            .filter_map(|l| {
                let f: Vec<&str> = l.split_whitespace().collect();
                (f.len() == n + 2 && f[0] == tag).then(|| {
                    let v = f[2..].iter().map(|w| number(w, l)).collect::<Result<Vec<u64>, String>>()?;
                    Ok((f[1].to_string(), v))
                })
            })
            .collect()
    }

    /// The first line tagged `tag`, at least `n` numbers.
    fn first(&self, tag: &str, n: usize) -> Result<Vec<u64>, String> {
        let rows = self.rows(tag)?;
        let row = rows.into_iter().next().ok_or_else(|| format!("the bench output has no `{tag}` line"))?;
        if row.len() < n {
            return Err(format!("the bench's `{tag}` line has {} numbers, expected {n}", row.len()));
        }
        Ok(row)
    }
}

fn number(word: &str, line: &str) -> Result<u64, String> {
    word.parse().map_err(|_| format!("{word:?} is not a number in the bench line {line:?}"))
}

/// `line` without ANSI colour sequences (`ESC [ digits/semicolons m`).
fn strip_ansi(line: &str) -> String {
    let mut out = String::with_capacity(line.len());
    let mut rest = line;
    while let Some(i) = rest.find('\x1b') {
        out.push_str(&rest[..i]);
        let after = &rest[i + 1..];
        let params = after.strip_prefix('[').map(|p| p.trim_start_matches(|c: char| c.is_ascii_digit() || c == ';'));
        match params.and_then(|p| p.strip_prefix('m')) {
            Some(tail) => rest = tail,
            None => {
                out.push('\x1b');
                rest = after;
            }
        }
    }
    out.push_str(rest);
    out
}

/// What `scripts/bench.sh` keeps of the `ui_firmware`, `firmware_e2e` and
/// `frame_budget` test runs: the draw-time table, the bus and UI stack
/// notes, the product firmware's stack high-water mark and the frame-budget
/// table.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct UiOutput {
    /// Rows after the `step  cycles …` header: step, cycles, ms, pixels,
    /// commands, as printed.
    pub steps: Vec<[String; 5]>,
    /// The `bus: …` and `stack: …` lines, in order.
    pub notes: Vec<String>,
    /// Bytes, from `firmware stack high-water: <n> B of …`.
    pub firmware_stack: Option<String>,
    /// The Markdown lines `frame_budget` prints behind `md:`.
    pub frame_budget: Vec<String>,
}

impl UiOutput {
    /// Reads the display and stack tests' `--nocapture` output; lines it does not know are skipped.
    pub fn parse(text: &str) -> UiOutput {
        let mut ui = UiOutput::default();
        let mut in_table = false;
        for line in text.lines() {
            let l = line.trim_end();
            if l.starts_with("step  cycles") {
                in_table = true;
                continue;
            }
            if in_table {
                let f: Vec<&str> = l.split_whitespace().collect();
                match <[&str; 5]>::try_from(f) {
                    Ok(row) if !row[0].is_empty() && row[0].bytes().all(|b| b.is_ascii_digit()) => {
                        ui.steps.push(row.map(str::to_string));
                        continue;
                    }
                    _ => in_table = false,
                }
            }
            if l.starts_with("bus:") || l.starts_with("stack:") {
                ui.notes.push(l.to_string());
            }
            if let Some(md) = l.strip_prefix("md:") {
                ui.frame_budget.push(md.trim().to_string());
            }
            if ui.firmware_stack.is_none() {
                if let Some(rest) = l.strip_prefix("firmware stack high-water:") {
                    ui.firmware_stack = rest.split('B').next().map(|v| v.trim().to_string());
                }
            }
        }
        ui
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bench_lines_are_cleaned_and_read_by_tag() {
        let text = "bench touch-arm 0.1.0\n\x1b[32mO 11\x1b[0m\nB frame 6778 3232 7000 1228 ...\n\
                    B short 1 2\nI plan_candidates 3 2 4\n\n  S 1278 6184.\nA 1 2 3 4 5 6 7\ndone\n";
        let b = BenchOutput::parse(text);
        assert_eq!(b.stamp_overhead(), Ok(11));
        assert_eq!(b.stack(), Ok((1278, 6184)));
        assert_eq!(
            b.routines().unwrap(),
            [Routine { name: "frame".into(), median: 6778, min: 3232, max: 7000, stack: 1228 }]
        );
        assert_eq!(b.counts().unwrap(), [Count { name: "plan_candidates".into(), median: 3, min: 2, max: 4 }]);
        assert_eq!(b.rows("A").unwrap(), [vec![1, 2, 3, 4, 5, 6, 7]]);
        assert_eq!(b.rows("E").unwrap(), Vec::<Vec<u64>>::new());
    }

    #[test]
    fn missing_or_garbled_lines_are_named() {
        let b = BenchOutput::parse("B frame 1 2 3 x\nS 5\n");
        assert_eq!(b.routines().unwrap_err(), "\"x\" is not a number in the bench line \"B frame 1 2 3 x\"");
        assert_eq!(b.stamp_overhead().unwrap_err(), "the bench output has no `O` line");
        assert_eq!(b.stack().unwrap_err(), "the bench's `S` line has 1 numbers, expected 2");
    }

    #[test]
    fn ansi_sequences_go_and_other_escapes_stay() {
        assert_eq!(strip_ansi("\x1b[1;31mred\x1b[0m plain"), "red plain");
        assert_eq!(strip_ansi("a\x1b[2Kb\x1b"), "a\x1b[2Kb\x1b");
    }

    #[test]
    fn ui_table_ends_at_the_first_other_line() {
        let text = "running 1 test\nbus: 9.02 cycles per pixel byte\nstep  cycles      ms   pixels  commands\n\
                    \x20  0  2711808  169.49    77838       709\n   1    51712    3.23     1500        16\n\
                    stack: 625 bytes at the deepest\n   2    51712    3.23     1500        16\n\
                    firmware stack high-water: 1799 B of 2048 B\nfirmware stack high-water: 1 B\n";
        let ui = UiOutput::parse(text);
        assert_eq!(ui.steps.len(), 2);
        assert_eq!(ui.steps[1], ["1", "51712", "3.23", "1500", "16"].map(String::from));
        assert_eq!(ui.notes, ["bus: 9.02 cycles per pixel byte", "stack: 625 bytes at the deepest"]);
        assert_eq!(ui.firmware_stack.as_deref(), Some("1799"));
        assert_eq!(UiOutput::parse("").firmware_stack, None);
        let fb = UiOutput::parse("md: | scenario | frames |\nmd: | --- | ---: |\nnoise\n");
        assert_eq!(fb.frame_budget, ["| scenario | frames |", "| --- | ---: |"]);
    }
}
