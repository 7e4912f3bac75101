//! gridplan's reports: a pure function from a sweep's results to its report files.
//!
//! summary.md is a list of [`Section`]s, each one kind of table: the scenario optima
//! ([`optimum`]), repeated runs ([`repeats`]), the aggregates of any sweep ([`aggregate`]),
//! planners compared problem by problem with a baseline ([`paired`]) and its charts
//! ([`chart_section`]) here; the seeds' table layouts are planner-paper's.
//! A config names the sections it wants with `sections = [...]` (a name, or a table with
//! its `name` and the section's options); without the key every section decides from the
//! experiment and its records whether it applies. Deterministic values come from repeat 0;
//! times are medians over repeats.
//!
//! [`Renderer`] turns a whole sweep's results ([`planner_runner::sweep::Results`]: the
//! experiment, its records, the expanded cells recorded at run time, the provenance) into
//! summary.md, the figures ([`figures`], [`coverage_figures`]), the charts ([`charts`]),
//! the OMPL logs ([`ompl`]), paths.jsonl and report.html ([`html`]). It runs no planner:
//! a results directory renders the same wherever it comes from (one run, merged shards,
//! `gridplan report DIR`). [`compare`] is likewise a function of two results directories
//! (`gridplan compare OLD NEW`).
#![deny(missing_docs)]
#![cfg_attr(not(test), warn(clippy::unwrap_used))]

pub mod aggregate;
pub mod chart_section;
pub mod charts;
pub mod compare;
pub mod coverage_figures;
pub mod exact;
pub mod figures;
pub mod html;
pub mod ompl;
pub mod optimum;
pub mod paired;
pub mod repeats;
pub mod streamed;

use std::fmt::Write as _;
use std::sync::atomic::AtomicBool;

use planner_runner::config::{ConfigError, Experiment};
use planner_runner::index::ResultsIndex;
use planner_runner::output::OutputFile;
use planner_runner::passes::RecordPasses;
use planner_runner::provenance::Provenance;
pub use planner_runner::record::Reproduction;
use planner_runner::record::RunRecord;
use planner_runner::sweep::{check_stop, Render, Results};
use planner_runner::RunnerError;

/// Largest number of map columns in one seed-000 style table, and of problems per map in
/// the per-problem tables.
pub const MAX_COLUMNS: usize = 12;

/// What a section reads.
pub struct Context<'a> {
    /// The experiment.
    pub experiment: &'a Experiment,
    /// Its records, in the run list's order.
    pub records: &'a [RunRecord],
    /// Lookups into the records.
    pub index: &'a ResultsIndex<'a>,
    /// The same records as passes ([`planner_runner::passes`]): the slice `records`, or,
    /// for a sweep too large to hold, its records read back from disk (and `records`
    /// empty; only the sections that [`Section::streams`] render then).
    pub passes: &'a dyn RecordPasses,
    /// The sweep's charts when they were computed before summary.md (by
    /// [`Renderer::files`], which writes them too), so the charts section links them
    /// without a second set of passes; `None`: the section computes them.
    pub charts: Option<&'a [charts::Chart]>,
    /// The section's options from the config (`sections = [{ name = ..., ... }]`; empty
    /// when the config names the section bare or names no sections).
    pub options: &'a toml::Table,
}

/// One part of summary.md.
pub trait Section: Send + Sync {
    /// The name configs use in `sections = [...]`.
    fn name(&self) -> &'static str;

    /// Whether the section has anything to say about this experiment (used when the
    /// config names no sections).
    fn applies(&self, context: &Context<'_>) -> bool;

    /// Checks the section's options (the config's table for it without `name`); by
    /// default a section takes none.
    fn check(&self, options: &toml::Table) -> Result<(), OptionError> {
        match options.keys().next() {
            Some(key) => Err(OptionError::Unknown {
                section: self.name().to_string(),
                key: key.clone(),
                only: None,
            }),
            None => Ok(()),
        }
    }

    /// The JSON Schema of the section's options, for `gridplan schema`: an object of
    /// `properties` (without `name`) and the `required` ones; by default none.
    fn options_schema(&self) -> serde_json::Value {
        serde_json::json!({ "properties": {} })
    }

    /// Checks the section's options against the experiment (options that name its labels);
    /// by default [`Section::check`].
    fn check_experiment(
        &self,
        options: &toml::Table,
        _experiment: &Experiment,
    ) -> Result<(), OptionError> {
        self.check(options)
    }

    /// Appends the section's markdown to `out` from the records held in memory
    /// (`records`, `index`) and counts compared published numbers. By default nothing: a
    /// section that gives a [`Section::table`] renders it in [`Section::render_passes`].
    fn render(&self, _context: &Context<'_>, _out: &mut String, _reproduction: &mut Reproduction) {}

    /// The section's whole markdown as one function of the experiment and passes over
    /// the records, when it is that (in memory bounded by the section's groups); by
    /// default none.
    fn table(&self) -> Option<PassesTable> {
        None
    }

    /// Appends the section's markdown to `out`: its [`Section::table`] from
    /// [`Context::passes`] if it has one, else [`Section::render`].
    fn render_passes(
        &self,
        context: &Context<'_>,
        out: &mut String,
        reproduction: &mut Reproduction,
    ) -> Result<(), RunnerError> {
        match self.table() {
            Some(table) => out.push_str(&table(context.experiment, context.passes)?),
            None => self.render(context, out, reproduction),
        }
        Ok(())
    }

    /// Whether [`Section::render_passes`] reads only [`Context::passes`] (not
    /// `records` or `index`), so that the section renders for a sweep too large to hold;
    /// by default whether the section has a [`Section::table`].
    fn streams(&self) -> bool {
        self.table().is_some()
    }
}

/// A section's markdown computed from the experiment and passes over its records
/// ([`Section::table`]).
pub type PassesTable = fn(&Experiment, &dyn RecordPasses) -> Result<String, RunnerError>;

/// A section's options that do not fit it (reported at the config's `sections` key).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum OptionError {
    /// An option the section does not take (`only`: the one it takes, if any).
    #[error(
        "section {section:?} takes no option `{key}`{}",
        .only.as_ref().map_or(String::new(), |only| format!(" (only `{only}`)"))
    )]
    Unknown {
        /// The section.
        section: String,
        /// The option given.
        key: String,
        /// The option the section takes, if any.
        only: Option<String>,
    },
    /// An option naming a planner, given as something else than a string.
    #[error("section {section:?}: `{key}` is a planner's registry name, a string")]
    NotAName {
        /// The section.
        section: String,
        /// The option.
        key: String,
    },
    /// An option naming a label, given as something else than a string.
    #[error("section {section:?}: `{key}` is a planner label of the config, a string")]
    NotALabel {
        /// The section.
        section: String,
        /// The option.
        key: String,
    },
    /// An option naming a label the config does not have.
    #[error("section {section:?}: no planner label {label:?}, expected one of {}", .labels.join(", "))]
    UnknownLabel {
        /// The section.
        section: String,
        /// The label given.
        label: String,
        /// The config's labels.
        labels: Vec<String>,
    },
    /// An option naming a planner (a registry name) that none of the config's labels runs.
    #[error(
        "section {section:?}: `{key} = {name:?}` names no planner of this config; expected the registry name of one of its planners ({})",
        .planners.join(", ")
    )]
    NotAPlanner {
        /// The section.
        section: String,
        /// The option.
        key: String,
        /// The name given.
        name: String,
        /// The registry names the config's labels run, each once, in label order.
        planners: Vec<String>,
    },
    /// A section's option naming a planner, missing.
    #[error(
        "section {section:?} needs `{key}`, the registry name of the planner it shows, e.g. {{ name = {section:?}, {key} = \"...\" }}"
    )]
    Missing {
        /// The section.
        section: String,
        /// The option.
        key: String,
    },
}

/// The generic sections of this crate, by name: `optimum`, `repeats`, `aggregate`,
/// `paired` and `charts`. A catalogue (planner-paper's) places them among the seeds' layouts.
pub fn generic_section(name: &str) -> Option<Box<dyn Section>> {
    let section: Box<dyn Section> = match name {
        "optimum" => Box::new(optimum::Optimum),
        "repeats" => Box::new(repeats::Repeats),
        "aggregate" => Box::new(aggregate::Aggregate),
        "paired" => Box::new(paired::Paired),
        "charts" => Box::new(chart_section::Charts),
        _ => return None,
    };
    Some(section)
}

/// A report: its catalogue of sections, in the order summary.md places them.
pub struct Renderer {
    sections: Vec<Box<dyn Section>>,
}

impl Renderer {
    /// A report with `sections`, in the order summary.md places them.
    pub fn new(sections: Vec<Box<dyn Section>>) -> Renderer {
        Renderer { sections }
    }

    /// The names of every section, for config errors and the config schema.
    pub fn section_names(&self) -> Vec<&'static str> {
        self.sections.iter().map(|s| s.name()).collect()
    }

    /// Every section's name with the schema of its options ([`Section::options_schema`]),
    /// in summary.md's order: what `gridplan schema` says `sections = [...]` takes.
    pub fn section_schemas(&self) -> Vec<(&'static str, serde_json::Value)> {
        self.sections
            .iter()
            .map(|s| (s.name(), s.options_schema()))
            .collect()
    }

    /// Renders summary.md and returns it with the reproduction counts.
    pub fn summary(
        &self,
        experiment: &Experiment,
        records: &[RunRecord],
    ) -> Result<(String, Reproduction), RunnerError> {
        self.summary_with(experiment, records, None)
    }

    /// Renders summary.md with the sweep's provenance at the top, if given: the records
    /// in memory read as passes ([`Renderer::summary_passes`]).
    pub fn summary_with(
        &self,
        experiment: &Experiment,
        records: &[RunRecord],
        provenance: Option<&Provenance>,
    ) -> Result<(String, Reproduction), RunnerError> {
        self.summary_passes(experiment, records, &records, provenance)
    }

    /// summary.md from passes over the records (`passes`; `records` the same records in
    /// memory, or empty when the sweep is too large to hold them), with the sweep's
    /// provenance at the top, if given. Sections that [`Section::streams`] render from
    /// the passes, in memory bounded by their groups; with `records` held the others
    /// render from them; else each of those is left out with a line that says so.
    pub fn summary_passes(
        &self,
        experiment: &Experiment,
        records: &[RunRecord],
        passes: &dyn RecordPasses,
        provenance: Option<&Provenance>,
    ) -> Result<(String, Reproduction), RunnerError> {
        self.summary_charted(experiment, records, passes, provenance, None, None)
    }

    /// [`Renderer::summary_passes`] with the sweep's charts already computed (`charts`;
    /// `None`: the charts section computes them); a raised `stop` ends it before the next
    /// section with [`RunnerError::Interrupted`].
    fn summary_charted(
        &self,
        experiment: &Experiment,
        records: &[RunRecord],
        passes: &dyn RecordPasses,
        provenance: Option<&Provenance>,
        charts: Option<&[charts::Chart]>,
        stop: Option<&AtomicBool>,
    ) -> Result<(String, Reproduction), RunnerError> {
        let held = records.len() as u64 == passes.len();
        let index = ResultsIndex::new(records);
        let empty = toml::Table::new();
        let mut out = String::new();
        let mut reproduction = Reproduction::default();
        if held {
            header(experiment, records, &mut out);
        } else {
            let first = experiment.planners.first().map(|p| p.label.as_str());
            let mut invalid = Vec::new();
            passes.pass(&mut |r| {
                if r.is_invalid() && Some(r.planner.as_str()) == first {
                    invalid.push(r.clone());
                }
            })?;
            header_of(experiment, passes.len(), &invalid, &mut out);
        }
        if let Some(provenance) = provenance {
            out.push_str(&provenance.markdown());
        }
        figure_notes(experiment, &mut out);
        // A large sweep's default tables: runs.parquet alone, which the sections name.
        if let Some(left_out) = experiment.outputs.left_out(passes.len()) {
            let _ = writeln!(out, "{left_out}\n");
        }
        let table = aggregate::runs_table(experiment, passes.len());
        for section in &self.sections {
            check_stop(stop)?;
            let options = match &experiment.sections {
                Some(asked) => match asked.get(section.name()) {
                    Some(request) => &request.options,
                    None => continue,
                },
                None => &empty,
            };
            let context = Context {
                experiment,
                records,
                index: &index,
                passes,
                charts,
                options,
            };
            if !held && !section.streams() {
                // Said for a section the config names; the others (whether they apply is
                // read from the records) are left out silently.
                if experiment.sections.is_none() {
                    continue;
                }
                let _ = writeln!(
                    out,
                    "Section `{}` is left out: it holds every record in memory, and this sweep's {} runs are more than the {} a report holds (see {table}).\n",
                    section.name(),
                    passes.len(),
                    HELD_RUNS
                );
                continue;
            }
            if experiment.sections.is_some() || section.applies(&context) {
                section.render_passes(&context, &mut out, &mut reproduction)?;
            }
        }
        Ok((out, reproduction))
    }

    /// Every report file of a whole sweep's results, in the order they are written:
    /// summary.md, figures, charts, OMPL logs (when the config asks), paths.jsonl (when
    /// the config keeps paths) and report.html. A sweep whose records are not held
    /// ([`Results::records`] empty: more than [`HELD_RUNS`] runs, or records over
    /// `planner_runner::sweep::HELD_BYTES`) gets summary.md's
    /// streamed sections, the charts (from passes) and the figures of its drawn problems
    /// (their records collected in one pass); its OMPL logs and `paths = "all"`'s
    /// paths.jsonl, which hold every record, are left out and summary.md says so, and
    /// `paths = "figures"`'s paths.jsonl is the runner's, written from a pass. A raised
    /// [`Results::stop`] ends it between its sections, figures and files with
    /// [`RunnerError::Interrupted`].
    pub fn files(
        &self,
        results: &Results<'_>,
    ) -> Result<(Vec<OutputFile>, Reproduction), RunnerError> {
        let experiment = results.experiment;
        let records = results.records;
        let passes = results.passes;
        let stop = results.stop;
        let held = records.len() as u64 == passes.len();
        // The charts once, for summary.md's links and for their files.
        let charts = charts::charts(experiment, passes)?;
        let (mut summary, reproduction) = self.summary_charted(
            experiment,
            records,
            passes,
            Some(results.provenance),
            Some(&charts),
            stop,
        )?;
        check_stop(stop)?;
        let drawn;
        let figure_records = if held {
            records
        } else {
            drawn = drawn_records(experiment, passes)?;
            drawn.as_slice()
        };
        let all_paths = experiment.paths == planner_runner::config::PathsMode::All;
        if !held && (experiment.ompl || all_paths) {
            let left_out = match (experiment.ompl, all_paths) {
                (true, true) => "OMPL logs and paths.jsonl are",
                (true, false) => "OMPL logs are",
                _ => "paths.jsonl is",
            };
            let _ = writeln!(
                summary,
                "{left_out} left out: they hold every record in memory, and this sweep's {} runs are more than the {HELD_RUNS} a report holds.\n",
                passes.len()
            );
        }
        let mut all = vec![OutputFile {
            path: "summary.md".into(),
            contents: summary.into_bytes(),
        }];
        all.extend(figures::render_until(
            experiment,
            figure_records,
            results.expanded,
            stop,
        )?);
        all.extend(charts::files(charts));
        check_stop(stop)?;
        if held && experiment.ompl {
            all.extend(ompl::logs(
                experiment,
                records,
                results.provenance,
                results.seconds,
            ));
        }
        // A sweep whose records are not held gets `paths = "figures"`'s paths.jsonl from
        // the runner, written from a pass (planner-runner's `sweep::PATHS_FILE`), and
        // `paths = "all"`'s not at all (summary.md says so).
        let paths = match held {
            true => planner_runner::output::paths_jsonl(figure_records)?,
            false => None,
        };
        if let Some(paths) = paths {
            all.push(OutputFile {
                path: planner_runner::sweep::PATHS_FILE.into(),
                contents: paths,
            });
        }
        check_stop(stop)?;
        let summary = String::from_utf8_lossy(&all[0].contents).into_owned();
        let page = html::report_html(&experiment.name, &summary, &all);
        all.push(OutputFile {
            path: "report.html".into(),
            contents: page.into_bytes(),
        });
        Ok((all, reproduction))
    }
}

/// The most runs whose records a sweep holds in memory for its report (the runner's
/// [`planner_runner::sweep::HELD_RUNS`]); above it only the sections that stream render.
pub const HELD_RUNS: u64 = planner_runner::sweep::HELD_RUNS;

/// A line per map whose figures the default limit leaves some problems out of
/// ([`Experiment::figure_limit`], when the config does not set `figures_per_map`).
fn figure_notes(experiment: &Experiment, out: &mut String) {
    if experiment.figures_per_map.is_some()
        || experiment.figures == planner_runner::config::FigureMode::None
    {
        return;
    }
    for map in &experiment.maps {
        let valid = map.problems.iter().filter(|p| p.invalid.is_none()).count();
        let limit = experiment.figure_limit(map);
        if valid > limit {
            let _ = writeln!(
                out,
                "Figures of {}: {limit} of its {valid} problems (`figures_pick`): without `figures_per_map`, as many as keep its figures within {} cells of drawn map, at most {}; `figures_per_map` sets how many.\n",
                md_cell(&map.name),
                planner_runner::config::DEFAULT_FIGURE_CELLS,
                planner_runner::config::DEFAULT_FIGURE_PROBLEMS
            );
        }
    }
}

/// The records the figures draw (repeat 0 of the drawn problems), from one pass: a few,
/// whatever the sweep's size (its paths.jsonl is written from a pass by the runner).
fn drawn_records(
    experiment: &Experiment,
    passes: &dyn RecordPasses,
) -> Result<Vec<RunRecord>, RunnerError> {
    let mut drawn = std::collections::HashSet::new();
    for map in &experiment.maps {
        if experiment.figures == planner_runner::config::FigureMode::None {
            break;
        }
        let limit = experiment.figure_limit(map);
        for problem in planner_runner::expanded::pick(&map.problems, experiment.figures_pick, limit)
        {
            drawn.insert((map.name.as_str(), problem.index));
        }
    }
    let mut records = Vec::new();
    passes.pass(&mut |r| {
        if r.repeat == 0 && drawn.contains(&(r.map.as_str(), r.problem)) {
            records.push(r.clone());
        }
    })?;
    Ok(records)
}

impl Render for Renderer {
    /// The config's `sections` name known sections, each with options it takes.
    fn check(&self, experiment: &Experiment) -> Result<(), ConfigError> {
        let Some(asked) = &experiment.sections else {
            return Ok(());
        };
        for request in &asked.requests {
            let Some(section) = self.sections.iter().find(|s| s.name() == request.name) else {
                return Err(asked.error(format!(
                    "unknown section {:?}, expected some of {}",
                    request.name,
                    self.section_names().join(", ")
                )));
            };
            section
                .check_experiment(&request.options, experiment)
                .map_err(|e| asked.error(e))?;
        }
        Ok(())
    }

    fn render(
        &self,
        results: &Results<'_>,
    ) -> Result<(Vec<OutputFile>, Reproduction), RunnerError> {
        self.files(results)
    }
}

fn header(experiment: &Experiment, records: &[RunRecord], out: &mut String) {
    let invalid: Vec<RunRecord> = records
        .iter()
        .filter(|r| {
            r.is_invalid() && Some(&r.planner) == experiment.planners.first().map(|p| &p.label)
        })
        .cloned()
        .collect();
    header_of(experiment, records.len() as u64, &invalid, out);
}

/// summary.md's head: the experiment, its `n_runs` runs, the inadmissible labels and the
/// `invalid` problems (the first label's invalid runs).
fn header_of(experiment: &Experiment, n_runs: u64, invalid: &[RunRecord], out: &mut String) {
    let _ = writeln!(out, "# Experiment `{}`\n", experiment.name);
    if let Some(description) = &experiment.description {
        let _ = writeln!(out, "{}\n", md_prose(description.trim()));
    }
    let n_problems: usize = experiment.maps.iter().map(|m| m.problems.len()).sum();
    let _ = writeln!(
        out,
        "Config {}: {} maps, {} problems, {} planner configurations, {} repeat(s), {} runs.\n",
        md_code(&experiment.source.display().to_string()),
        experiment.maps.len(),
        n_problems,
        experiment.planners.len(),
        experiment.repeats,
        n_runs
    );
    let inadmissible: Vec<String> = experiment
        .planners
        .iter()
        .filter(|p| p.factory.specs().admissible == Some(false))
        .map(|p| md_code(&p.label))
        .collect();
    if !inadmissible.is_empty() {
        let _ = writeln!(
            out,
            "Not optimal by design: {} {} paths that need not be least-cost (for A*: a heuristic that can overestimate under its moves, or a weight above 1); {} runs are recorded `admissible = false`.\n",
            inadmissible.join(", "),
            if inadmissible.len() == 1 { "declares" } else { "declare" },
            if inadmissible.len() == 1 { "its" } else { "their" }
        );
    }
    if !invalid.is_empty() {
        let _ = writeln!(out, "Invalid problems (not run):\n");
        for r in invalid {
            let _ = writeln!(
                out,
                "- {} problem {} {} -> {}: {}",
                md_cell(&r.map),
                r.problem,
                r.start,
                r.goal,
                r.error.as_deref().unwrap_or("invalid")
            );
        }
        out.push('\n');
    }
}

/// The median and interquartile range (quartiles by linear interpolation between order
/// statistics, the "type 7" rule of R and numpy's default) of `values`.
pub fn median_iqr(values: &[f64]) -> Option<(f64, f64, f64)> {
    if values.is_empty() {
        return None;
    }
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    let q = |p: f64| {
        let h = (sorted.len() - 1) as f64 * p;
        let lo = h.floor() as usize;
        let hi = h.ceil() as usize;
        sorted[lo] + (h - lo as f64) * (sorted[hi] - sorted[lo])
    };
    Some((q(0.5), q(0.25), q(0.75)))
}

/// `text` as part of a file name: ASCII letters, digits, `-`, `_` and `.` are kept and any
/// other character becomes `_`; if any did, a `-` and the first 8 hex digits of the
/// SHA-256 of `text` follow, so that names differing only in replaced characters (`p q`
/// and `p_q`) stay apart. Names of plain characters are unchanged. A name longer than
/// [`FILE_PART_MAX`] characters keeps its first [`FILE_PART_MAX`] and gets the hash too:
/// a file name holds at most 255 bytes on Linux's file systems, and a figure's name joins
/// a map's and a planner's (a 251-character map name made every figure's write fail with
/// "File name too long" after the runs). [`FileNames`] also catches the names that would
/// still meet (one output per name).
///
/// ```
/// use planner_report::{file_part, FILE_PART_MAX};
/// assert_eq!(file_part("map01"), "map01");
/// assert_ne!(file_part("p q"), file_part("p_q"));
/// assert!(file_part("p q").starts_with("p_q-"));
/// let long = "a".repeat(300);
/// assert_eq!(file_part(&long).len(), FILE_PART_MAX + 9);
/// assert_ne!(file_part(&long), file_part(&"a".repeat(301)));
/// ```
pub fn file_part(text: &str) -> String {
    let mut safe: String = text
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.') {
                c
            } else {
                '_'
            }
        })
        .collect();
    if safe == text && !text.is_empty() && !text.starts_with('.') && safe.len() <= FILE_PART_MAX {
        return safe;
    }
    // Every character of `safe` is ASCII, so any length is a character boundary.
    safe.truncate(FILE_PART_MAX);
    format!("{safe}-{}", short_hash(text))
}

/// The most characters of a user's text [`file_part`] keeps: two of them, the hashes and
/// the longest fixed parts of a figure's name (`-<problem>-...-expanded.svg`) stay well
/// below 255 bytes.
pub const FILE_PART_MAX: usize = 96;

/// Each name's position among `names`, the first where it repeats.
pub(crate) fn positions<'a>(
    names: impl DoubleEndedIterator<Item = &'a str> + ExactSizeIterator,
) -> std::collections::HashMap<&'a str, usize> {
    names.enumerate().rev().map(|(i, name)| (name, i)).collect()
}

/// The first 8 hex digits of the SHA-256 of `text`.
pub(crate) fn short_hash(text: &str) -> String {
    use sha2::{Digest, Sha256};
    Sha256::digest(text.as_bytes())
        .iter()
        .take(4)
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// The output file names of one kind handed out so far, so that two outputs never share
/// one: [`FileNames::claim`] returns the name asked for, or, when another output took it
/// already, that name with the hash of what this output is (its `key`, e.g. map, problem
/// and label) before the extension, and a counter should that be taken too. Names are
/// compared without letter case (`Case-1.svg` takes `case-1.svg` too): on a
/// case-insensitive file system (macOS's and Windows' defaults) they are one file.
#[derive(Debug, Default)]
pub struct FileNames {
    /// The names handed out, lowercased.
    used: std::collections::HashSet<String>,
}

impl FileNames {
    /// A name for the output `key`, `wanted` if free (`wanted` ends in `.ext`).
    ///
    /// ```
    /// let mut names = planner_report::FileNames::default();
    /// assert_eq!(names.claim("ompl/Case.log".into(), "Case.map"), "ompl/Case.log");
    /// assert_ne!(names.claim("ompl/case.log".into(), "case.map"), "ompl/case.log");
    /// ```
    pub fn claim(&mut self, wanted: String, key: &str) -> String {
        if self.used.insert(wanted.to_lowercase()) {
            return wanted;
        }
        let (stem, ext) = wanted
            .rsplit_once('.')
            .map_or((wanted.as_str(), ""), |(s, e)| (s, e));
        let dot = if ext.is_empty() { "" } else { "." };
        let hashed = format!("{stem}-{}", short_hash(key));
        let mut candidate = format!("{hashed}{dot}{ext}");
        let mut n = 2;
        while !self.used.insert(candidate.to_lowercase()) {
            candidate = format!("{hashed}-{n}{dot}{ext}");
            n += 1;
        }
        candidate
    }
}

/// Markdown escaping of what users write: planner-text's, shared with the runner's tables
/// and the replanning experiments.
pub use planner_text::{md_cell, md_code, md_prose};

#[cfg(test)]
mod tests {
    use super::median_iqr;

    #[test]
    fn quartiles_follow_type_7() {
        // numpy.percentile([1, 2, 3, 4], [25, 50, 75]) = [1.75, 2.5, 3.25].
        assert_eq!(median_iqr(&[4.0, 1.0, 3.0, 2.0]), Some((2.5, 1.75, 3.25)));
        assert_eq!(median_iqr(&[7.0]), Some((7.0, 7.0, 7.0)));
        assert_eq!(median_iqr(&[]), None);
    }
}
