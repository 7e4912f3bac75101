//! The sweep's result tables, runs.csv and runs.json, as bytes or written row by row to
//! a writer ([`StreamedFile`]); replacing a results directory safely is
//! [`crate::outdir`]'s job.

use std::fmt::Write as _;
use std::io::Write;
use std::path::PathBuf;

use crate::config::Experiment;
use crate::passes::RecordPasses;
use crate::record::RunRecord;
use crate::RunnerError;

/// A file of the results directory.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct OutputFile {
    /// Relative path, e.g. `figures/map01-1-astar.svg`.
    pub path: PathBuf,
    /// Contents.
    pub contents: Vec<u8>,
}

/// A results file written straight to disk by a function (the large tables), instead
/// of held as bytes: [`crate::outdir::write_results_streamed`] calls `write` with a
/// buffered writer on the file.
pub struct StreamedFile<'a> {
    /// Relative path, e.g. `runs.csv`.
    pub path: PathBuf,
    /// Writes the contents (to a `Send` writer: the Parquet writer needs one).
    #[allow(clippy::type_complexity)]
    pub write: Box<dyn Fn(&mut (dyn Write + Send)) -> Result<(), RunnerError> + 'a>,
}

/// One result table format of `outputs = [...]` (issue 29).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum TableFormat {
    /// runs.csv.
    Csv,
    /// runs.json (pandas' "split" table with the header).
    Json,
    /// The Parquet dataset `runs.parquet/` ([`crate::columnar`]).
    Parquet,
}

/// Which result tables a sweep writes (`outputs = [...]`; default all three, or, for a sweep
/// of more than [`crate::sweep::HELD_RUNS`] runs, runs.parquet only: [`Outputs::for_runs`]).
/// The records.stream that `report` reads, summary.md and the other report files are
/// written whatever it says. It is not part of the config hash: a sweep resumed or merged
/// with another `outputs` writes that one's tables from the same records.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Outputs {
    /// runs.csv.
    pub csv: bool,
    /// runs.json.
    pub json: bool,
    /// runs.parquet/.
    pub parquet: bool,
    /// Whether the config named them (`outputs = [...]`), rather than left the default.
    pub named: bool,
}

impl Default for Outputs {
    fn default() -> Outputs {
        Outputs {
            csv: true,
            json: true,
            parquet: true,
            named: false,
        }
    }
}

impl Outputs {
    /// The tables a whole sweep of `runs` runs writes: the named ones; by default all three
    /// up to [`crate::sweep::HELD_RUNS`] runs, and above only runs.parquet (about 160 and
    /// 140 bytes a run of runs.json and runs.csv are left out; name them to have them,
    /// written row by row from the records on disk).
    ///
    /// ```
    /// use planner_runner::output::Outputs;
    /// let large = Outputs::default().for_runs(10_000_000);
    /// assert!(large.parquet && !large.csv && !large.json);
    /// assert_eq!(Outputs::default().for_runs(1_000), Outputs::default());
    /// ```
    pub fn for_runs(self, runs: u64) -> Outputs {
        if self.named || runs <= crate::sweep::HELD_RUNS {
            return self;
        }
        Outputs {
            csv: false,
            json: false,
            ..self
        }
    }

    /// The table a reader of these outputs is pointed at for a column (summary.md's "every
    /// bucket is in runs.csv's `bucket` column"): runs.csv when it is written, else
    /// runs.parquet, else runs.json.
    ///
    /// ```
    /// use planner_runner::output::Outputs;
    /// assert_eq!(Outputs::default().for_runs(1_000).table(), "runs.csv");
    /// assert_eq!(Outputs::default().for_runs(10_000_000).table(), "runs.parquet");
    /// ```
    pub fn table(self) -> &'static str {
        match (self.csv, self.parquet) {
            (true, _) => "runs.csv",
            (false, true) => "runs.parquet",
            (false, false) => "runs.json",
        }
    }

    /// What [`Outputs::for_runs`] leaves out of a whole sweep of `runs` runs, as a sentence
    /// for summary.md and the command line (`None` when it writes every table asked for):
    /// runs.csv and runs.json, when the config does not name its tables and the sweep has
    /// more than [`crate::sweep::HELD_RUNS`] runs.
    ///
    /// ```
    /// use planner_runner::output::Outputs;
    /// assert!(Outputs::default().left_out(1_000).is_none());
    /// let notice = Outputs::default().left_out(200_000).unwrap();
    /// assert!(notice.starts_with("runs.csv and runs.json are not written"));
    /// ```
    pub fn left_out(self, runs: u64) -> Option<String> {
        let written = self.for_runs(runs);
        let left: Vec<&str> = [
            (self.csv && !written.csv, "runs.csv"),
            (self.json && !written.json, "runs.json"),
        ]
        .into_iter()
        .filter_map(|(left, name)| left.then_some(name))
        .collect();
        let verb = if left.len() == 1 { "is" } else { "are" };
        (!left.is_empty()).then(|| {
            format!(
                "{} {verb} not written: this sweep's {runs} runs are more than the {} whose result tables are all written by default (runs.csv and runs.json take about 140 and 160 bytes a run); runs.parquet holds every run, and `outputs = [\"csv\", \"json\", \"parquet\"]` writes them all at any size.",
                left.join(" and "),
                crate::sweep::HELD_RUNS
            )
        })
    }

    /// The tables of `formats` (at least one; a format named twice is written once).
    pub fn of(formats: &[TableFormat]) -> Option<Outputs> {
        (!formats.is_empty()).then(|| Outputs {
            named: true,
            csv: formats.contains(&TableFormat::Csv),
            json: formats.contains(&TableFormat::Json),
            parquet: formats.contains(&TableFormat::Parquet),
        })
    }
}

/// The columns of runs.csv, runs.parquet and runs.json's table that every run has (the
/// columns some runs have and the counters follow).
pub const FIXED_COLUMNS: [&str; 21] = [
    "map",
    "problem",
    "start_x",
    "start_y",
    "goal_x",
    "goal_y",
    "planner",
    "algorithm",
    "repeat",
    "seed",
    "status",
    "steps",
    "turns",
    "score",
    "length",
    "optimal_length",
    "valid",
    "time_ms",
    "setup_ms",
    "peak_heap_bytes",
    "bucket",
];

/// Columns of runs.json that appear only when some record has a value in them.
const OPTIONAL_COLUMNS: [&str; 6] = ["error", "admissible", "returns", "marks", "series", "cost"];

/// Columns of runs.csv and runs.parquet, after the [`FIXED_COLUMNS`], that appear only
/// when some record has a value in them: why a run was refused or its problem is invalid
/// (`error`), and a weighted map's path cost (`cost`). runs.json has both among its
/// optional columns, in the same order.
pub const SOMETIMES_COLUMNS: [&str; 2] = ["error", "cost"];

/// The columns of one runs.csv or runs.parquet beyond the [`FIXED_COLUMNS`]: the
/// [`SOMETIMES_COLUMNS`] some record has a value in, and every counter name in order of
/// first appearance. Gathered in a pass over the records ([`TableColumns::add`]).
#[derive(Debug, Clone, Default)]
pub struct TableColumns {
    /// Whether some record has each of the [`SOMETIMES_COLUMNS`].
    sometimes: [bool; 2],
    /// The counter names.
    counters: Vec<String>,
}

impl TableColumns {
    /// Adds what `record` has.
    pub fn add(&mut self, record: &RunRecord) {
        self.sometimes[0] |= record.error.is_some();
        self.sometimes[1] |= record.cost.is_some();
        add_counter_names(&mut self.counters, record);
    }

    /// The columns of records gathered by a pass over `records`.
    pub fn of(records: &dyn RecordPasses) -> Result<TableColumns, RunnerError> {
        let mut columns = TableColumns::default();
        records.pass(&mut |r| columns.add(r))?;
        Ok(columns)
    }

    /// The positions in [`SOMETIMES_COLUMNS`] of the columns the table has.
    pub(crate) fn sometimes(&self) -> impl Iterator<Item = usize> + '_ {
        (0..SOMETIMES_COLUMNS.len()).filter(|&i| self.sometimes[i])
    }

    /// The counter columns.
    pub fn counters(&self) -> &[String] {
        &self.counters
    }

    /// Every column name of the table, in order.
    pub fn names(&self) -> Vec<&str> {
        FIXED_COLUMNS
            .iter()
            .copied()
            .chain(self.sometimes().map(|i| SOMETIMES_COLUMNS[i]))
            .chain(self.counters.iter().map(String::as_str))
            .collect()
    }
}

/// The runs as JSON (`runs.json`): `{"experiment", "config", "runs": {"columns": [...],
/// "data": [[...], ...]}}`, one run per row, one row per line, in run order. The table
/// holds runs.csv's columns, typed (numbers, `true`/`false`, strings, `null` for an empty
/// cell), and more: the [`FIXED_COLUMNS`], then `error`, `admissible`, `returns`, `marks`,
/// `series` and `cost` (a weighted map's path cost) when some run has one (a value or
/// `null`), then one column per counter in order of first appearance (`null` where a run
/// lacks it); runs.csv has `error` and `cost` of these ([`SOMETIMES_COLUMNS`]). Paths are
/// not in it (`paths.jsonl`). Times are rounded to the nanosecond (1e-6 ms), the clock's
/// resolution; an invalid problem's run, never run, has `null` time, setup time and peak
/// heap. `runs` is pandas' "split" layout: `pandas.DataFrame(**json.load(f)["runs"])`
/// is the table.
///
/// With `provenance`, the header also holds it (`"provenance"`) and every label's resolved
/// parameters (`"planners"`).
pub fn runs_json(experiment: &Experiment, records: &[RunRecord]) -> Result<Vec<u8>, RunnerError> {
    runs_json_with(experiment, records, None)
}

/// [`runs_json`] with the sweep's provenance and the labels' resolved parameters.
pub fn runs_json_with(
    experiment: &Experiment,
    records: &[RunRecord],
    provenance: Option<&crate::provenance::Provenance>,
) -> Result<Vec<u8>, RunnerError> {
    let mut out = Vec::with_capacity(records.len() * 160 + 1024);
    write_runs_json(&mut out, experiment, records, provenance)?;
    Ok(out)
}

fn io(e: std::io::Error) -> RunnerError {
    RunnerError::Json(serde_json::Error::io(e))
}

/// Writes [`runs_json_with`]'s bytes to `out`, row by row.
pub fn write_runs_json(
    out: &mut dyn Write,
    experiment: &Experiment,
    records: &[RunRecord],
    provenance: Option<&crate::provenance::Provenance>,
) -> Result<(), RunnerError> {
    write_runs_json_passes(out, experiment, &records, provenance)
}

/// [`write_runs_json`] from two passes over the records (the columns, then the rows), in
/// memory bounded by a row: a sweep too large to hold its records writes runs.json so.
pub fn write_runs_json_passes(
    out: &mut dyn Write,
    experiment: &Experiment,
    records: &dyn RecordPasses,
    provenance: Option<&crate::provenance::Provenance>,
) -> Result<(), RunnerError> {
    write_header(out, experiment, provenance)?;
    let mut counter_names = Vec::new();
    let mut optional = [false; 6];
    records.pass(&mut |r| {
        add_counter_names(&mut counter_names, r);
        let used = [
            r.error.is_some(),
            r.admissible.is_some(),
            r.returns.is_some(),
            !r.marks.is_empty(),
            !r.series.is_empty(),
            r.cost.is_some(),
        ];
        for (o, u) in optional.iter_mut().zip(used) {
            *o |= u;
        }
    })?;
    let columns: Vec<&str> = FIXED_COLUMNS
        .iter()
        .copied()
        .chain(
            OPTIONAL_COLUMNS
                .iter()
                .zip(optional)
                .filter(|(_, used)| *used)
                .map(|(c, _)| *c),
        )
        .chain(counter_names.iter().map(String::as_str))
        .collect();
    out.write_all(b",\"runs\":{\"columns\":").map_err(io)?;
    serde_json::to_writer(&mut *out, &columns).map_err(RunnerError::Json)?;
    out.write_all(b",\"data\":[").map_err(io)?;
    let mut row = Vec::with_capacity(512);
    let mut first = true;
    let mut failed = None;
    records.pass(&mut |r| {
        if failed.is_some() {
            return;
        }
        row.clear();
        row.extend_from_slice(if first { b"\n[" } else { b",\n[" });
        first = false;
        let written = encode_row(&mut row, r, &optional, &counter_names).and_then(|()| {
            // The last cell's comma closes the row.
            if let Some(last) = row.last_mut() {
                *last = b']';
            }
            out.write_all(&row).map_err(io)
        });
        failed = written.err();
    })?;
    if let Some(e) = failed {
        return Err(e);
    }
    out.write_all(b"\n]}}\n").map_err(io)?;
    Ok(())
}

/// runs.json's header: the experiment, its config, and with `provenance` that and every
/// label's planner, resolved parameters and budget.
fn write_header(
    out: &mut dyn Write,
    experiment: &Experiment,
    provenance: Option<&crate::provenance::Provenance>,
) -> Result<(), RunnerError> {
    let json = |out: &mut dyn Write, value: &dyn erased::Value| value.write_json(out);
    out.write_all(b"{\"experiment\":").map_err(io)?;
    json(out, &experiment.name)?;
    out.write_all(b",\"config\":").map_err(io)?;
    json(out, &experiment.source.display().to_string())?;
    if let Some(provenance) = provenance {
        out.write_all(b",\"provenance\":").map_err(io)?;
        serde_json::to_writer(&mut *out, provenance).map_err(RunnerError::Json)?;
        let planners: serde_json::Map<String, serde_json::Value> = experiment
            .planners
            .iter()
            .map(|p| {
                let entry = serde_json::json!({
                    "planner": p.name,
                    "parameters": p.parameters(experiment.seed),
                    "budget": p.budget,
                });
                (p.label.clone(), entry)
            })
            .collect();
        out.write_all(b",\"planners\":").map_err(io)?;
        serde_json::to_writer(&mut *out, &planners).map_err(RunnerError::Json)?;
    }
    Ok(())
}

/// One row of runs.json's table into `row`, each cell followed by a comma: the fixed
/// columns, the `optional` ones in use, the counters named `counter_names`.
fn encode_row(
    row: &mut Vec<u8>,
    r: &RunRecord,
    optional: &[bool; 6],
    counter_names: &[String],
) -> Result<(), RunnerError> {
    let cell = |row: &mut Vec<u8>, value: &dyn erased::Value| -> Result<(), RunnerError> {
        value.write_json(row)?;
        row.push(b',');
        Ok(())
    };
    cell(row, &r.map)?;
    cell(row, &r.problem)?;
    cell(row, &r.start.x)?;
    cell(row, &r.start.y)?;
    cell(row, &r.goal.x)?;
    cell(row, &r.goal.y)?;
    cell(row, &r.planner)?;
    cell(row, &r.algorithm)?;
    cell(row, &r.repeat)?;
    cell(row, &r.seed)?;
    cell(row, &r.status.as_str())?;
    cell(row, &r.steps)?;
    cell(row, &r.turns)?;
    cell(row, &r.score)?;
    cell(row, &r.length)?;
    cell(row, &r.optimal_length)?;
    cell(row, &r.valid)?;
    cell(row, &measured(r, nanoseconds(r.time_ms)))?;
    cell(row, &measured(r, nanoseconds(r.setup_ms)))?;
    cell(row, &measured(r, r.peak_heap_bytes))?;
    cell(row, &r.bucket)?;
    if optional[0] {
        cell(row, &r.error)?;
    }
    if optional[1] {
        cell(row, &r.admissible)?;
    }
    if optional[2] {
        cell(row, &r.returns)?;
    }
    if optional[3] {
        cell(row, &(!r.marks.is_empty()).then_some(&r.marks))?;
    }
    if optional[4] {
        cell(row, &(!r.series.is_empty()).then_some(&r.series))?;
    }
    if optional[5] {
        cell(row, &r.cost)?;
    }
    for value in counter_values(&r.counters, counter_names) {
        cell(row, &value)?;
    }
    Ok(())
}

/// `ms` rounded to the nanosecond.
fn nanoseconds(ms: f64) -> f64 {
    (ms * 1e6).round() / 1e6
}

/// Values written as JSON, through one object-safe trait.
mod erased {
    use std::io::Write;

    use crate::RunnerError;

    /// A value serde writes as JSON.
    pub trait Value {
        /// Writes the value's JSON to `out`.
        fn write_json(&self, out: &mut dyn Write) -> Result<(), RunnerError>;
    }

    impl<T: serde::Serialize + ?Sized> Value for T {
        fn write_json(&self, out: &mut dyn Write) -> Result<(), RunnerError> {
            serde_json::to_writer(out, self).map_err(RunnerError::Json)
        }
    }
}

/// The values of `counters` under `names`, in that order (`None` where absent). A run
/// usually reports its counters in the order of `names`: each is then found at the next
/// position, with one comparison.
fn counter_values<'a>(
    counters: &'a planner_api::Counters,
    names: &'a [String],
) -> impl Iterator<Item = Option<u64>> + 'a {
    let mut reported = counters.iter().peekable();
    names.iter().map(move |name| match reported.peek() {
        Some(&(next, value)) if next == name => {
            reported.next();
            Some(value)
        }
        _ => counters.get(name),
    })
}

/// Adds the counter names of `record` that `names` lacks, in its order (every counter name
/// of a sweep's records, in order of first appearance, after a pass).
fn add_counter_names(names: &mut Vec<String>, record: &RunRecord) {
    for (name, _) in record.counters.iter() {
        if !names.iter().any(|n| n == name) {
            names.push(name.to_string());
        }
    }
}

/// The runs as CSV: the [`FIXED_COLUMNS`], then those of the [`SOMETIMES_COLUMNS`] (`error`,
/// `cost`) that some run has, then one column per counter name in order of first
/// appearance; a run without a value there leaves the cell empty (an invalid problem's
/// run, never run, its time, setup time and peak heap). Floats are the shortest decimal
/// that reads back as the same double ([`csv_float`]; runs.json's and runs.parquet's value),
/// times rounded to the nanosecond as there.
pub fn runs_csv(records: &[RunRecord]) -> Vec<u8> {
    let mut out = Vec::with_capacity(records.len() * 140 + 512);
    // Writing to a Vec cannot fail.
    let _ = write_runs_csv(&mut out, records);
    out
}

/// Writes [`runs_csv`]'s bytes to `out`, row by row.
pub fn write_runs_csv(out: &mut dyn Write, records: &[RunRecord]) -> Result<(), RunnerError> {
    write_runs_csv_passes(out, &records)
}

/// [`write_runs_csv`] from two passes over the records (the columns, then the rows), in
/// memory bounded by a row.
pub fn write_runs_csv_passes(
    out: &mut dyn Write,
    records: &dyn RecordPasses,
) -> Result<(), RunnerError> {
    let columns = TableColumns::of(records)?;
    let sometimes: Vec<usize> = columns.sometimes().collect();
    let mut line = columns.names().join(",");
    line.push('\n');
    out.write_all(line.as_bytes()).map_err(io)?;
    let mut failed = None;
    records.pass(&mut |r| {
        if failed.is_some() {
            return;
        }
        line.clear();
        let cells = (0..FIXED_COLUMNS.len())
            .map(|i| fixed_cell(r, i))
            .chain(sometimes.iter().map(|&i| sometimes_cell(r, i)));
        for (i, cell) in cells.enumerate() {
            if i > 0 {
                line.push(',');
            }
            // The column walk runs.parquet shares; floats as the shortest decimal that
            // reads back as the same double (times rounded to the nanosecond first).
            match cell {
                Cell::Text(text) => text.into_iter().for_each(|text| {
                    line.push_str(&planner_text::csv_field(text));
                }),
                Cell::Unsigned(v) => v.into_iter().for_each(|v| {
                    let _ = write!(line, "{v}");
                }),
                Cell::Float(v) => v.into_iter().for_each(|v| {
                    let v = if matches!(i, TIME_MS | SETUP_MS) {
                        nanoseconds(v)
                    } else {
                        v
                    };
                    let _ = write!(line, "{}", csv_float(v));
                }),
                Cell::Boolean(v) => v.into_iter().for_each(|v| {
                    let _ = write!(line, "{v}");
                }),
            }
        }
        for value in counter_values(&r.counters, columns.counters()) {
            line.push(',');
            if let Some(v) = value {
                let _ = write!(line, "{v}");
            }
        }
        line.push('\n');
        failed = out.write_all(line.as_bytes()).map_err(io).err();
    })?;
    failed.map_or(Ok(()), Err)
}

/// `v` as runs.csv writes it: the shortest decimal that reads back as the same double
/// (Rust's round-trip formatting), with a `.0` on a whole number so that pandas and DuckDB
/// type the column as floats, and an exponent below 1e-4 and from 1e16 (`1e-7`, `1e16`),
/// which both read. Not finite (never in a record): empty, as JSON's `null`.
pub fn csv_float(v: f64) -> String {
    if v.is_finite() {
        format!("{v:?}")
    } else {
        String::new()
    }
}

/// One cell of a row of runs.csv and runs.parquet: a column's value for one record
/// (`None` for an empty cell).
pub(crate) enum Cell<'r> {
    /// A string column.
    Text(Option<&'r str>),
    /// An unsigned integer column.
    Unsigned(Option<u64>),
    /// A float column (times in milliseconds, unrounded: each table rounds them).
    Float(Option<f64>),
    /// A boolean column.
    Boolean(Option<bool>),
}

/// Column `time_ms` of [`FIXED_COLUMNS`].
pub(crate) const TIME_MS: usize = 17;

/// Column `setup_ms` of [`FIXED_COLUMNS`].
pub(crate) const SETUP_MS: usize = 18;

/// Column `peak_heap_bytes` of [`FIXED_COLUMNS`].
pub(crate) const PEAK_HEAP_BYTES: usize = 19;

/// A measurement of `r` (its time, setup time or peak heap): `None` for an invalid
/// problem, which was not run, so that its empty cell is no 0 a mean would count.
pub(crate) fn measured<T>(r: &RunRecord, value: T) -> Option<T> {
    (!r.is_invalid()).then_some(value)
}

/// Column `i` of [`FIXED_COLUMNS`] for `r`: the one column walk of runs.csv and
/// runs.parquet, which render the cells each in their own way.
pub(crate) fn fixed_cell(r: &RunRecord, i: usize) -> Cell<'_> {
    let u = |v: u64| Cell::Unsigned(Some(v));
    match i {
        0 => Cell::Text(Some(&r.map)),
        1 => u(r.problem as u64),
        2 => u(u64::from(r.start.x)),
        3 => u(u64::from(r.start.y)),
        4 => u(u64::from(r.goal.x)),
        5 => u(u64::from(r.goal.y)),
        6 => Cell::Text(Some(&r.planner)),
        7 => Cell::Text(Some(&r.algorithm)),
        8 => u(u64::from(r.repeat)),
        9 => Cell::Unsigned(r.seed),
        10 => Cell::Text(Some(r.status.as_str())),
        11 => Cell::Unsigned(r.steps),
        12 => Cell::Unsigned(r.turns),
        13 => Cell::Unsigned(r.score),
        14 => Cell::Float(r.length),
        15 => Cell::Float(r.optimal_length),
        16 => Cell::Boolean(r.valid),
        TIME_MS => Cell::Float(measured(r, r.time_ms)),
        SETUP_MS => Cell::Float(measured(r, r.setup_ms)),
        PEAK_HEAP_BYTES => Cell::Unsigned(measured(r, r.peak_heap_bytes)),
        _ => Cell::Unsigned(r.bucket.map(u64::from)),
    }
}

/// Column `i` of [`SOMETIMES_COLUMNS`] for `r`, as [`fixed_cell`] gives the others.
pub(crate) fn sometimes_cell(r: &RunRecord, i: usize) -> Cell<'_> {
    match i {
        0 => Cell::Text(r.error.as_deref()),
        _ => Cell::Float(r.cost),
    }
}

/// The kept paths as JSON Lines, one `{"map","problem","planner","repeat","path"}` object per
/// record that has a path, in record order (`paths.jsonl`; runs.json then leaves `path`
/// null). `None` when no record has a path.
pub fn paths_jsonl(records: &[RunRecord]) -> Result<Option<Vec<u8>>, RunnerError> {
    let mut out = Vec::new();
    for r in records {
        write_path_line(&mut out, r)?;
    }
    Ok((!out.is_empty()).then_some(out))
}

/// `record`'s line of paths.jsonl ([`paths_jsonl`]), if it has a path.
pub fn write_path_line(out: &mut dyn Write, record: &RunRecord) -> Result<(), RunnerError> {
    #[derive(serde::Serialize)]
    struct Line<'a> {
        map: &'a str,
        problem: usize,
        planner: &'a str,
        repeat: u32,
        path: &'a planner_api::Path,
    }
    if let Some(path) = &record.path {
        let line = Line {
            map: &record.map,
            problem: record.problem,
            planner: &record.planner,
            repeat: record.repeat,
            path,
        };
        serde_json::to_writer(&mut *out, &line).map_err(RunnerError::Json)?;
        out.write_all(b"\n").map_err(io)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// runs.json's table holds what runs.csv holds, typed, plus the optional columns a
    /// run uses (PA-star's marks), and no path.
    #[test]
    fn the_json_table_matches_the_records_and_the_csv() {
        let map = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../maps/paper/map01.map")
            .display()
            .to_string();
        let text = format!(
            "name = \"t\"\nrepeats = 2\npaths = \"all\"\n[[maps]]\nfiles = [{map:?}]\nproblems = \"corners\"\n[planners.a]\nplanner = \"astar\"\n[planners.p]\nplanner = \"pastar\"\n"
        );
        let experiment = crate::config::parse(std::path::Path::new("t.toml"), &text).unwrap();
        let records = crate::run_all(&experiment, &crate::RunOptions::default()).unwrap();
        let json: serde_json::Value =
            serde_json::from_slice(&runs_json(&experiment, &records).unwrap()).unwrap();
        let columns: Vec<&str> = json["runs"]["columns"]
            .as_array()
            .unwrap()
            .iter()
            .map(|c| c.as_str().unwrap())
            .collect();
        let csv = String::from_utf8(runs_csv(&records)).unwrap();
        let csv_columns: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
        // The CSV's columns, with `marks` (PA-star's handover points) before the counters.
        let marks = columns.iter().position(|&c| c == "marks").unwrap();
        assert_eq!(marks, FIXED_COLUMNS.len());
        let without_marks: Vec<&str> = columns
            .iter()
            .enumerate()
            .filter(|&(i, _)| i != marks)
            .map(|(_, c)| *c)
            .collect();
        assert_eq!(without_marks, csv_columns);
        assert!(!columns.contains(&"path"));
        let rows = json["runs"]["data"].as_array().unwrap();
        assert_eq!(rows.len(), records.len());
        let at = |name: &str| columns.iter().position(|&c| c == name).unwrap();
        for (row, record) in rows.iter().zip(&records) {
            assert_eq!(row.as_array().unwrap().len(), columns.len());
            assert_eq!(row[at("map")], record.map.as_str());
            assert_eq!(row[at("repeat")], record.repeat);
            assert_eq!(row[at("status")], record.status.as_str());
            assert_eq!(row[at("steps")].as_u64(), record.steps);
            assert_eq!(row[at("length")].as_f64(), record.length);
            assert_eq!(
                row[at("n_expanded")].as_u64(),
                record.counters.get("n_expanded")
            );
            let time = row[at("time_ms")].as_f64().unwrap();
            assert!(
                (time - record.time_ms).abs() <= 5e-7,
                "{time} {}",
                record.time_ms
            );
            assert_eq!(row[marks].is_null(), record.marks.is_empty());
        }
        assert!(records.iter().any(|r| !r.marks.is_empty()));
    }
}
