//! `armsim paper`: the two papers' worked examples and figures, and the lab
//! note's paths, computed by this implementation from the inputs the papers
//! state (issue #23; docs/armsim-paper.md). Every number comes from the core's
//! trajectory code (`touch_arm::motion::{zat, via, path}`) through the same
//! plans `armsim traj`, `via` and `path` use; where the papers' printed form
//! or claim is wrong the item says so and links docs/corrections.md.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use clap::Args;
use touch_arm::motion::Sample;

use crate::path::PathKind;
use crate::plot::{self, Curve, Panel};
use crate::report::csv_row;

mod items;
pub mod poly;

pub use items::{compute, via_values, ITEMS, VIA_TOL};

/// `armsim paper` arguments: `list`, `all --out DIR`, or one item's id.
#[derive(Args, Debug)]
pub struct PaperArgs {
    /// `list`, `all`, or an item id (see `armsim paper list`)
    pub id: String,
    /// Print the item's JSON {"id", "inputs", "values"} instead of text
    #[arg(long)]
    pub json: bool,
    /// Draw the item's figure to FILE (.png or .svg)
    #[arg(long, value_name = "FILE")]
    pub plot: Option<PathBuf>,
    /// Write the item's samples to FILE (CSV)
    #[arg(long, value_name = "FILE")]
    pub csv: Option<PathBuf>,
    /// With `all`: the directory for every item's JSON, CSV, figure and report.md
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
}

/// One value of an item's JSON.
#[derive(Debug, Clone, PartialEq)]
pub enum Val {
    /// A number (`null` when not finite).
    Num(f64),
    /// A count.
    Int(u64),
    /// A yes/no property.
    Bool(bool),
    /// A name.
    Str(&'static str),
    /// A list of numbers.
    Arr(Vec<f64>),
    /// No value (an iteration that diverges).
    Null,
}

impl Val {
    /// The value as JSON, numbers in shortest round-trip form.
    pub fn json(&self) -> String {
        match self {
            Val::Num(x) => jnum(*x),
            Val::Int(n) => n.to_string(),
            Val::Bool(b) => b.to_string(),
            Val::Str(s) => format!("\"{s}\""),
            Val::Arr(v) => format!("[{}]", v.iter().map(|x| jnum(*x)).collect::<Vec<_>>().join(", ")),
            Val::Null => "null".into(),
        }
    }
}

/// A finite f64 in the shortest form that reads back as the same f64
/// (Rust's `{:?}`: `{}`'s digits, with an exponent far from 1, as
/// serde_json writes them); `null` otherwise.
pub fn jnum(x: f64) -> String {
    if x.is_finite() {
        format!("{x:?}")
    } else {
        "null".into()
    }
}

/// One computed quantity: its JSON key, value, the formula used, and the
/// anchor in docs/corrections.md when the formula departs from the print.
#[derive(Debug, Clone)]
pub struct Quantity {
    /// The JSON key (issue #23's name).
    pub key: &'static str,
    /// The value.
    pub value: Val,
    /// The formula it was computed with.
    pub formula: &'static str,
    /// The heading anchor in docs/corrections.md, where a correction applies.
    pub correction: Option<&'static str>,
}

/// The samples an item's figure and CSV show.
#[derive(Debug, Clone)]
pub enum Figure {
    /// Curves over time: per curve a label and (s, v, acc, jerk) samples;
    /// the first `shown` of position, velocity, acceleration, jerk are drawn.
    Series {
        /// Figure title.
        title: String,
        /// Sample times, s.
        t: Vec<f64>,
        /// (label, samples) per curve.
        curves: Vec<(String, Vec<Sample<f64>>)>,
        /// How many of s, v, acc, jerk the figure shows (the paper's).
        shown: usize,
    },
    /// An end-effector path, drawn and sampled as `armsim path` does.
    Path(PathKind),
}

/// One item computed: what `armsim paper <id>` prints, plots and writes.
#[derive(Debug, Clone)]
pub struct Item {
    /// The item's id.
    pub id: &'static str,
    /// One line saying what it is.
    pub about: &'static str,
    /// The inputs as the paper states them (JSON "inputs").
    pub inputs: Vec<(&'static str, Val)>,
    /// The values (JSON "values").
    pub values: Vec<Quantity>,
    /// Where the print and the computation disagree, divergence, choices made.
    pub notes: Vec<String>,
    /// The figure's samples.
    pub figure: Figure,
}

/// Where the corrections live, relative to the repository root.
pub const CORRECTIONS: &str = "docs/corrections.md";

impl Item {
    /// `{"id": ..., "inputs": {...}, "values": {...}}` on one line.
    pub fn json(&self) -> String {
        let obj = |kv: &mut dyn Iterator<Item = (&str, &Val)>| {
            format!("{{{}}}", kv.map(|(k, v)| format!("\"{k}\": {}", v.json())).collect::<Vec<_>>().join(", "))
        };
        let inputs = obj(&mut self.inputs.iter().map(|(k, v)| (*k, v)));
        let values = obj(&mut self.values.iter().map(|q| (q.key, &q.value)));
        format!("{{\"id\": \"{}\", \"inputs\": {inputs}, \"values\": {values}}}", self.id)
    }

    /// The value of `key`, if the item has it.
    pub fn value(&self, key: &str) -> Option<&Val> {
        self.values.iter().find(|q| q.key == key).map(|q| &q.value)
    }

    /// The text report: inputs, each value with its formula, the notes.
    pub fn text(&self) -> String {
        let inputs: Vec<String> = self.inputs.iter().map(|(k, v)| format!("{k} = {}", v.json())).collect();
        let mut s = format!("{}: {}\ninputs: {}\n", self.id, self.about, inputs.join(", "));
        let w = self.values.iter().map(|q| q.key.len()).max().unwrap_or(0);
        for q in &self.values {
            let _ = write!(s, "  {:w$} = {}   [{}]", q.key, q.value.json(), q.formula);
            if let Some(c) = q.correction {
                let _ = write!(s, " (correction: {CORRECTIONS}#{c})");
            }
            s.push('\n');
        }
        for n in &self.notes {
            let _ = writeln!(s, "note: {n}");
        }
        s
    }

    /// The samples as CSV: `t` and per curve s, v, acc, jerk (suffixed by
    /// the curve's label when there are several); a path's
    /// `t,x,y,z,th1,th2,th3` as `armsim path` writes it.
    pub fn csv(&self) -> Result<String, String> {
        match &self.figure {
            Figure::Series { t, curves, .. } => {
                let mut head = vec!["t".to_string()];
                for (label, _) in curves {
                    for q in ["s", "v", "acc", "jerk"] {
                        head.push(if curves.len() > 1 { format!("{q}_{label}") } else { q.to_string() });
                    }
                }
                let mut out = head.join(",") + "\n";
                for (i, &ti) in t.iter().enumerate() {
                    let mut row = vec![ti];
                    for (_, s) in curves {
                        row.extend([s[i].s, s[i].v, s[i].acc, s[i].jerk]);
                    }
                    out.push_str(&csv_row(&row));
                    out.push('\n');
                }
                Ok(out)
            }
            Figure::Path(k) => crate::path::cmd_path(k),
        }
    }

    /// Draws the figure to `out` (.png or .svg).
    pub fn plot(&self, out: &Path) -> Result<(), String> {
        match &self.figure {
            Figure::Series { title, t, curves, shown } => {
                let names = ["position", "velocity", "acceleration", "jerk"];
                let cols: Vec<Vec<Vec<f64>>> = curves
                    .iter()
                    .map(|(_, s)| {
                        vec![
                            s.iter().map(|x| x.s).collect(),
                            s.iter().map(|x| x.v).collect(),
                            s.iter().map(|x| x.acc).collect(),
                            s.iter().map(|x| x.jerk).collect(),
                        ]
                    })
                    .collect();
                let label = |i: usize| if curves.len() > 1 { curves[i].0.as_str() } else { "" };
                let panels: Vec<Panel<'_>> = (0..*shown)
                    .map(|q| Panel {
                        ylabel: names[q],
                        curves: (0..curves.len()).map(|c| Curve { label: label(c), y: &cols[c][q] }).collect(),
                    })
                    .collect();
                plot::panels(out, title, t, &panels).map_err(|e| e.to_string())
            }
            Figure::Path(k) => {
                crate::path::plot_path(&crate::path::PlotPath { kind: k.clone(), out: Some(out.to_path_buf()) })
                    .map(|_| ())
            }
        }
    }
}

/// `armsim paper list`: every item with its one-line description.
fn list() -> String {
    let w = ITEMS.iter().map(|(id, _)| id.len()).max().unwrap_or(0);
    ITEMS.iter().map(|(id, about)| format!("{id:w$}  {about}\n")).collect()
}

/// The report's table row cells of one item.
fn report_rows(item: &Item) -> String {
    let mut s = String::new();
    for q in &item.values {
        let corr = q.correction.map_or(String::from("none"), |c| format!("[{c}]({CORRECTIONS}#{c})"));
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} |",
            item.id,
            q.key,
            q.value.json(),
            q.formula.replace('|', "\\|"),
            corr
        );
    }
    s
}

/// `DIR/report.md`: one table over every item, then each item's notes.
pub fn report(items: &[Item]) -> String {
    let mut s = String::from(
        "# armsim paper: the papers' examples computed\n\n\
         Generated by `armsim paper all`. Inputs as the papers state them; values from this\n\
         implementation (f64). Corrections link to docs/corrections.md in the repository.\n\n\
         | item | quantity | value | formula used | correction |\n| --- | --- | --- | --- | --- |\n",
    );
    for it in items {
        s.push_str(&report_rows(it));
    }
    s.push_str("\n## Notes: print against computation\n\n");
    for it in items {
        for n in &it.notes {
            let _ = writeln!(s, "- **{}**: {n}", it.id);
        }
    }
    s
}

/// `armsim paper all --out DIR`: every item's `<id>.json`, `<id>.csv` and
/// `<id>.svg`, and `report.md`. Returns the paths written.
pub fn write_all(dir: &Path) -> Result<Vec<PathBuf>, String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let mut written = Vec::new();
    let mut items = Vec::new();
    for (id, _) in ITEMS {
        let item = compute(id)?;
        let write = |name: String, body: &str, written: &mut Vec<PathBuf>| {
            let p = dir.join(name);
            std::fs::write(&p, body).map_err(|e| format!("{}: {e}", p.display()))?;
            written.push(p);
            Ok::<(), String>(())
        };
        write(format!("{id}.json"), &(item.json() + "\n"), &mut written)?;
        write(format!("{id}.csv"), &item.csv()?, &mut written)?;
        let fig = dir.join(format!("{id}.svg"));
        item.plot(&fig)?;
        written.push(fig);
        items.push(item);
    }
    let rep = dir.join("report.md");
    std::fs::write(&rep, report(&items)).map_err(|e| format!("{}: {e}", rep.display()))?;
    written.push(rep);
    Ok(written)
}

/// Runs `armsim paper ...` and returns what it prints.
pub fn run(a: &PaperArgs) -> Result<String, String> {
    let single_only = a.json || a.plot.is_some() || a.csv.is_some();
    match a.id.as_str() {
        "list" if !single_only && a.out.is_none() => Ok(list()),
        "list" => Err("`paper list` takes no options".into()),
        "all" => {
            if single_only {
                return Err("`paper all` takes only --out DIR".into());
            }
            let dir = a.out.as_ref().ok_or("`paper all` needs --out DIR")?;
            let files = write_all(dir)?;
            Ok(files.iter().map(|p| format!("wrote {}\n", p.display())).collect())
        }
        id => {
            if a.out.is_some() {
                return Err("--out is for `paper all`; one item takes --plot FILE and --csv FILE".into());
            }
            let item = compute(id)?;
            let mut out = if a.json { item.json() + "\n" } else { item.text() };
            if let Some(p) = &a.csv {
                std::fs::write(p, item.csv()?).map_err(|e| format!("{}: {e}", p.display()))?;
                if !a.json {
                    let _ = writeln!(out, "wrote {}", p.display());
                }
            }
            if let Some(p) = &a.plot {
                item.plot(p)?;
                if !a.json {
                    let _ = writeln!(out, "wrote {}", p.display());
                }
            }
            Ok(out)
        }
    }
}
