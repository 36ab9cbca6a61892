//! A first model file, annotated, from data files or from nothing (`dampid init`).
//!
//! From data files, each file becomes one `[[data.records]]` entry with its columns
//! guessed by name (case-insensitive): a column named `t` or starting with `time` is the
//! time column (else the first other column that increases at a uniform step, with a
//! jitter below [`crate::io::table::MAX_TIME_JITTER`]); columns `x…`, `q…`, `disp…` are
//! displacements, `v…`, `vel…` velocities, `a…`, `acc…` accelerations, `f…`, `force…`
//! forces. A force column whose name ends in a number k ≤ n acts on DOF k (as `dampid
//! simulate` names them), else on DOF 1. n is the largest number of motion columns of
//! one kind in one file. The driving period is detected from the force columns
//! ([`crate::prep::period::detect_period`]) and written as `period`, with its explained
//! share. Every guess is written with a comment saying it is one; the damping model
//! starts as one linear dashpot per link of a chain.
//!
//! From nothing, the file simulates a 2-DOF chain (unit masses, unit springs, walls at
//! both ends, eigenvalues 1 and 3 of tridiag(−1, 2, −1), so ω₁ = 1 and ω₂ = √3), driven
//! at both natural frequencies, with 1% sensor noise, and identifies one dashpot per
//! link: it runs as written, and its `[data]` section is a commented example.

use std::fmt;
use std::path::Path;

use faer::Mat;

use crate::io::Table;
use crate::prep::period::{PeriodEstimate, detect_period};

/// What `init` found in one data file.
#[derive(Debug, Clone, PartialEq)]
pub struct InitRecord {
    /// The path the model file names it by (relative to the model file).
    pub file: String,
    /// Every column, in file order.
    pub columns: Vec<String>,
    /// The guessed time column and its mean step.
    pub time: Option<(String, f64)>,
    /// Guessed displacement columns.
    pub displacements: Vec<String>,
    /// Guessed velocity columns.
    pub velocities: Vec<String>,
    /// Guessed acceleration columns.
    pub accelerations: Vec<String>,
    /// Guessed force columns and the DOF (1-based) each acts on.
    pub forces: Vec<(String, usize)>,
    /// The detected driving period, when the force shows one.
    pub period: Option<PeriodEstimate>,
    /// Why no period was detected.
    pub no_period: Option<String>,
    /// What a MAT file holds: every variable, struct and field by path (listed in the
    /// comments; empty for other formats).
    pub contents: Vec<crate::io::mat::Entry>,
    /// Arrays of the file that are not columns of the record, each with why.
    pub left_out: Vec<String>,
}

/// The annotated model file `init` writes, and what it found.
#[derive(Debug, Clone, PartialEq)]
pub struct InitModel {
    /// The model file's text.
    pub text: String,
    /// Number of DOFs.
    pub dofs: usize,
    /// One entry per data file (empty for the template from nothing).
    pub records: Vec<InitRecord>,
}

/// Motion and force kinds a column name may announce.
#[derive(Clone, Copy, PartialEq)]
enum Kind {
    Displacement,
    Velocity,
    Acceleration,
    Force,
}

/// The kind a column name announces, by its prefix.
fn kind_of(name: &str) -> Option<Kind> {
    let lower = name.to_ascii_lowercase();
    let starts = |prefixes: &[&str]| {
        prefixes.iter().any(|p| {
            lower.starts_with(p)
                && lower[p.len()..]
                    .chars()
                    .next()
                    .is_none_or(|c| !c.is_ascii_alphabetic() || p.len() > 1)
        })
    };
    if starts(&["disp", "x", "q"]) {
        Some(Kind::Displacement)
    } else if starts(&["vel", "v"]) {
        Some(Kind::Velocity)
    } else if starts(&["acc", "a"]) {
        Some(Kind::Acceleration)
    } else if starts(&["force", "f"]) {
        Some(Kind::Force)
    } else {
        None
    }
}

/// The number a column name ends with (`f4` → 4, `x[12]` → 12).
fn trailing_number(name: &str) -> Option<usize> {
    let trimmed = name.trim_end_matches(']');
    let digits: String = trimmed
        .chars()
        .rev()
        .take_while(char::is_ascii_digit)
        .collect::<Vec<_>>()
        .into_iter()
        .rev()
        .collect();
    digits.parse().ok()
}

/// The time column: by name, else the first column that increases at a uniform step.
fn time_column(table: &Table) -> Option<(String, f64)> {
    let named = table.headers.iter().find(|h| {
        let lower = h.to_ascii_lowercase();
        lower == "t" || lower.starts_with("time")
    });
    let candidates = named.into_iter().chain(table.headers.iter());
    for name in candidates {
        if let Ok(step) = table.uniform_step(name) {
            return Some((name.clone(), step.step));
        }
    }
    None
}

impl InitRecord {
    /// The guesses for `table`, named `file` in the model file.
    pub fn guess(file: &str, table: &Table) -> InitRecord {
        let time = time_column(table);
        let mut record = InitRecord {
            file: file.to_string(),
            columns: table.headers.clone(),
            time: time.clone(),
            displacements: Vec::new(),
            velocities: Vec::new(),
            accelerations: Vec::new(),
            forces: Vec::new(),
            period: None,
            no_period: None,
            contents: Vec::new(),
            left_out: Vec::new(),
        };
        let mut forces = Vec::new();
        for name in &table.headers {
            if time.as_ref().is_some_and(|(t, _)| t == name) {
                continue;
            }
            match kind_of(name) {
                Some(Kind::Displacement) => record.displacements.push(name.clone()),
                Some(Kind::Velocity) => record.velocities.push(name.clone()),
                Some(Kind::Acceleration) => record.accelerations.push(name.clone()),
                Some(Kind::Force) => forces.push(name.clone()),
                None => {}
            }
        }
        let n = record.motion_columns().max(1);
        record.forces = forces
            .into_iter()
            .map(|name| {
                let dof = trailing_number(&name)
                    .filter(|k| (1..=n).contains(k))
                    .unwrap_or(1);
                (name, dof)
            })
            .collect();
        match (&time, record.forces.is_empty()) {
            (None, _) => record.no_period = Some("no time column was found".into()),
            (_, true) => record.no_period = Some("no force column was found".into()),
            (Some((_, step)), false) => {
                let names: Vec<String> = record.forces.iter().map(|(f, _)| f.clone()).collect();
                let detected = table
                    .matrix(&names)
                    .and_then(|m: Mat<f64>| detect_period(m.as_ref(), *step, file));
                match detected {
                    Ok(p) => record.period = Some(p),
                    Err(e) => record.no_period = Some(e.to_string()),
                }
            }
        }
        record
    }

    /// The number of motion columns of the kind the record is read by.
    fn motion_columns(&self) -> usize {
        self.displacements
            .len()
            .max(self.velocities.len())
            .max(self.accelerations.len())
    }

    /// The columns no guess assigned.
    pub fn unassigned(&self) -> Vec<&str> {
        self.columns
            .iter()
            .filter(|c| {
                self.time.as_ref().is_none_or(|(t, _)| t != *c)
                    && !self.displacements.contains(c)
                    && !self.velocities.contains(c)
                    && !self.accelerations.contains(c)
                    && !self.forces.iter().any(|(f, _)| f == *c)
            })
            .map(String::as_str)
            .collect()
    }
}

/// How a model file at `model` names the data file `file`: relative to the model
/// file's folder when it lies below it, else its absolute path.
pub fn path_in_model(file: &Path, model: &Path) -> String {
    let folder = match model.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let absolute = |p: &Path| std::fs::canonicalize(p).unwrap_or_else(|_| p.to_path_buf());
    let (file, folder) = (absolute(file), absolute(folder));
    file.strip_prefix(&folder)
        .map(Path::to_path_buf)
        .unwrap_or(file)
        .to_string_lossy()
        .into_owned()
}

/// A TOML basic string: a JSON string is one (the same escapes, UTF-8 as is).
fn quoted(s: &str) -> String {
    serde_json::Value::from(s).to_string()
}

fn quoted_list(items: &[String]) -> String {
    let items: Vec<String> = items.iter().map(|s| quoted(s)).collect();
    format!("[{}]", items.join(", "))
}

const HEADER: &str = "\
# A model file written by `dampid init`. Every section and key, with its type, default
# and unit: docs/model-file.md. Check the guesses marked `guess`, then run
#   dampid check <this file>      (periods, steady state, conditioning)
#   dampid identify <this file>   (the fit)
";

const TERMS: &str = "\
# The damping model: one linear (viscous) dashpot per link of a chain of the DOFs,
# walls at 0 and n + 1: coefficients dashpot[0-1] … dashpot[n-(n+1)], in force per unit
# velocity. Other laws: quadratic, coulomb, power (parameters = { exponent = 1.5 }),
# expression; other places: elements = \"each_dof\" (each DOF to ground) or
# [[a, b], …] (DOF pairs, 0 = ground); one shared coefficient = \"c\" instead of
# per_element.
[[terms]]
kind = \"law\"
law = \"linear\"
elements = \"chain\"
per_element = \"dashpot\"
";

const IDENTIFICATION: &str = "\
# How to identify (every key has a default; see docs/model-file.md).
[identification]
quadrature = \"trapezoid\"     # rectangular, trapezoid or spectral
cycles = 1                   # whole periods per window (one equation per window)
# velocity = \"spectral\"      # default: harmonic projection of the displacements
# nonnegative = true         # every coefficient ≥ 0
";

/// The annotated model file for `records` (one per data file), or the runnable
/// template when `records` is empty.
pub fn init(records: Vec<InitRecord>) -> InitModel {
    if records.is_empty() {
        return InitModel {
            text: template(),
            dofs: 2,
            records,
        };
    }
    let dofs = records
        .iter()
        .map(InitRecord::motion_columns)
        .max()
        .unwrap_or(0)
        .max(1);
    let mut text = String::from(HEADER);
    text.push_str(&format!(
        "title = \"Identified from {} file(s)\"\ndofs = {dofs}                     # guess: the most motion columns of one kind in one file\n\n",
        records.len()
    ));
    text.push_str(TERMS);
    text.push('\n');
    text.push_str(IDENTIFICATION);
    for r in &records {
        text.push_str(&data_record(r, dofs));
    }
    InitModel {
        text,
        dofs,
        records,
    }
}

/// One `[[data.records]]` entry with its comments.
fn data_record(r: &InitRecord, dofs: usize) -> String {
    let mut s = String::new();
    s.push_str(&format!(
        "\n# {}: columns {}\n",
        r.file,
        r.columns.join(", ")
    ));
    s.push_str(&contents_comment(r));
    let unassigned = r.unassigned();
    if !unassigned.is_empty() {
        s.push_str(&format!(
            "# not assigned (neither time, motion nor force by name): {}\n",
            unassigned.join(", ")
        ));
    }
    s.push_str("[[data.records]]\n");
    s.push_str(&format!("file = {}\n", quoted(&r.file)));
    match &r.time {
        Some((t, step)) => s.push_str(&format!(
            "time = {}                 # guess: mean step {}\n",
            quoted(t),
            crate::format::number(*step)
        )),
        None => s.push_str(
            "step = 1.0                 # no time column found: give the sampling step\n",
        ),
    }
    // One motion kind per DOF: displacements when there are any, else velocities,
    // else accelerations. Velocities beside displacements for every DOF are read as
    // measured velocities (velocity = "measured" in [identification]).
    let (key, motion) = if !r.displacements.is_empty() {
        ("displacements", &r.displacements)
    } else if !r.velocities.is_empty() {
        ("velocities", &r.velocities)
    } else {
        ("accelerations", &r.accelerations)
    };
    if motion.is_empty() {
        s.push_str(&format!(
            "displacements = {}       # no motion column found: name one per DOF\n",
            quoted_list(&(1..=dofs).map(|k| format!("x{k}")).collect::<Vec<_>>())
        ));
    } else {
        s.push_str(&format!(
            "{key} = {}   # guess: DOF 1, 2, … in this order\n",
            quoted_list(motion)
        ));
    }
    if key == "displacements" && !r.velocities.is_empty() {
        s.push_str(&format!(
            "# velocities = {}   # measured velocities, used with velocity = \"measured\"\n",
            quoted_list(&r.velocities)
        ));
    }
    if r.forces.is_empty() {
        s.push_str("forces = [{ column = \"f1\", dof = 1 }]   # no force column found: name it and its DOF\n");
    } else {
        let forces: Vec<String> = r
            .forces
            .iter()
            .map(|(c, dof)| format!("{{ column = {}, dof = {dof} }}", quoted(c)))
            .collect();
        s.push_str(&format!(
            "forces = [{}]   # guess: the DOF from the column's number, else 1\n",
            forces.join(", ")
        ));
    }
    match (&r.period, &r.no_period) {
        (Some(p), _) => s.push_str(&format!(
            "period = {}   # detected from the force: {:.1}% of its variance at ω = {}, {:.2} periods in the record\n",
            crate::format::number(p.period),
            100.0 * p.explained,
            crate::format::number(p.frequency),
            p.cycles
        )),
        (None, Some(why)) => s.push_str(&format!(
            "# period = 1.0   # not detected ({}): give the period or frequency\n",
            why.replace('\n', " ")
        )),
        (None, None) => {}
    }
    s
}

/// The comment lines listing what a MAT file holds (path, size and class, a char
/// array's text), what is left out of the columns, and the struct arrays that read as
/// stepped-sine sweeps.
fn contents_comment(r: &InitRecord) -> String {
    const SHOWN: usize = 200;
    let mut s = String::new();
    if !r.contents.is_empty() {
        s.push_str("# what the MAT file holds (path: size class):\n");
        let width = r
            .contents
            .iter()
            .take(SHOWN)
            .map(|e| e.path.chars().count())
            .max()
            .unwrap_or(0);
        for e in r.contents.iter().take(SHOWN) {
            let text = e
                .text
                .as_ref()
                .map(|t| format!(" {}", quoted(t)))
                .unwrap_or_default();
            s.push_str(&format!("#   {:width$}  {}{text}\n", e.path, e.description));
        }
        if r.contents.len() > SHOWN {
            s.push_str(&format!("#   … {} more\n", r.contents.len() - SHOWN));
        }
        // Struct arrays of vectors: stepped-sine sweeps, read by `sweeps`.
        let arrays: Vec<&str> = r
            .contents
            .iter()
            .filter(|e| e.description.ends_with(" struct") && !e.description.starts_with("1×1 "))
            .map(|e| e.path.as_str())
            .collect();
        if !arrays.is_empty() {
            s.push_str(&format!(
                "# struct arrays (a stepped-sine table of one sweep per element reads them as\n# [stepped_sine] file = {}, sweeps = {}, columns named by field; docs/stepped_sine.md): {}\n",
                quoted(&r.file),
                quoted_list(&arrays.iter().map(|a| a.to_string()).collect::<Vec<_>>()),
                arrays.join(", ")
            ));
        }
    }
    if !r.left_out.is_empty() {
        s.push_str(&format!(
            "# not columns of this record: {}\n",
            r.left_out.join("; ").replace('\n', " ")
        ));
    }
    s
}

/// The runnable template: a simulated 2-DOF chain (module doc).
fn template() -> String {
    let mut text = String::from(HEADER);
    text.push_str(
        "\
# This template simulates its own records, so it runs as written: a chain of two unit
# masses between walls (springs of stiffness 1), damped by one dashpot per link.
title = \"Two-mass chain (template)\"
dofs = 2                     # number of DOFs (sensors), numbered from 1; 0 is ground

",
    );
    text.push_str(TERMS);
    text.push('\n');
    text.push_str(IDENTIFICATION);
    text.push_str(
        "\
# Records generated by simulation: M x'' + damping + K x = a cos(ωt + φ) on one DOF.
# Replace this section by [[data.records]] (below) to identify from measurements.
[simulation]
mass = \"identity\"            # a [matrices] name, \"identity\", \"chain\" or inline rows
stiffness = \"chain\"          # tridiag(−1, 2, −1): natural frequencies ω = 1 and √3
coefficients = { \"dashpot[0-1]\" = 0.1, \"dashpot[1-2]\" = 0.05, \"dashpot[2-3]\" = 0.15 }
step = 0.05                  # recording step h (time units)
substeps = 2                 # RK4 steps per recorded step
transient_steps = 6000       # 300 time units dropped so the motion is steady
recorded_steps = 800         # 40 time units recorded: 6 periods at ω = 1
noise = 0.01                 # Gaussian sensor noise, 1% of each channel's RMS, on every channel
noise_seed = 1               # the same seed, the same records

[[simulation.experiments]]
force_dof = 1                # the DOF driven, 1-based
amplitude = 1.0              # a (force units)
frequency = 1.0              # ω (rad per time unit): mode 1

[[simulation.experiments]]
force_dof = 2
amplitude = 1.0
frequency = 1.7320508075688772   # √3: mode 2

[[simulation.experiments]]
force_dof = 1
amplitude = 1.0
frequency = 1.7320508075688772

# From measured files instead (delete [simulation] and its experiments; paths are
# relative to this file; `dampid init data/*.csv` writes this for your files):
# [[data.records]]
# file = \"data/run_1.csv\"
# time = \"t\"                             # or step = h
# displacements = [\"x1\", \"x2\"]            # one column per DOF (or velocities, accelerations)
# forces = [{ column = \"f1\", dof = 1 }]   # force columns and the DOF each acts on
# period = 6.2832                        # or frequency = ω; absent: detected from the force
",
    );
    text
}

impl fmt::Display for InitRecord {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: ", self.file)?;
        match &self.time {
            Some((t, step)) => write!(f, "time {t} (step {})", crate::format::number(*step))?,
            None => write!(f, "no time column")?,
        }
        let motion = [
            ("displacements", &self.displacements),
            ("velocities", &self.velocities),
            ("accelerations", &self.accelerations),
        ];
        for (kind, columns) in motion.iter().filter(|(_, c)| !c.is_empty()) {
            write!(f, ", {kind} {}", columns.join(" "))?;
        }
        let forces: Vec<String> = self
            .forces
            .iter()
            .map(|(c, d)| format!("{c} on DOF {d}"))
            .collect();
        if !forces.is_empty() {
            write!(f, ", forces {}", forces.join(" "))?;
        }
        match &self.period {
            Some(p) => write!(f, ", period {}", crate::format::number(p.period)),
            None => write!(f, ", period not detected"),
        }
    }
}

impl fmt::Display for InitModel {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.records.is_empty() {
            return writeln!(
                f,
                "a 2-DOF chain that simulates its own records (replace [simulation] by [[data.records]] for measured data)"
            );
        }
        writeln!(f, "{} DOF(s) (guess)", self.dofs)?;
        for r in &self.records {
            writeln!(f, "{r}")?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_announce_kinds() {
        assert!(kind_of("x1") == Some(Kind::Displacement));
        assert!(kind_of("disp_3") == Some(Kind::Displacement));
        assert!(kind_of("v2") == Some(Kind::Velocity));
        assert!(kind_of("acc[1]") == Some(Kind::Acceleration));
        assert!(kind_of("F4") == Some(Kind::Force));
        assert!(kind_of("force") == Some(Kind::Force));
        // A word that only starts with the letter is not the kind.
        assert!(kind_of("amplitude").is_none());
        assert!(kind_of("temperature").is_none());
        assert_eq!(trailing_number("f12"), Some(12));
        assert_eq!(trailing_number("x[3]"), Some(3));
        assert_eq!(trailing_number("force"), None);
    }
}
