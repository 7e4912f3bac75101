//! The runs as Apache Parquet (issue 29): runs.csv's columns, typed, in row groups of at
//! most [`ROW_GROUP_ROWS`] runs compressed with snappy, with the experiment, its config,
//! the provenance and the planner table in the file's key-value metadata. Written with the
//! `parquet` crate's low-level column writer (no Arrow).
//!
//! Layout: a results directory holds the Parquet files in their own dataset directory,
//! [`PARQUET_DIR`] (`runs.parquet/`, as Spark writes a table), one file per shard named
//! by [`part_name`]: `part-1-of-1.parquet` for a whole sweep or a merge,
//! `part-K-of-N.parquet` in shard K's directory. So `pandas.read_parquet("x/runs.parquet")`
//! reads one sweep without tripping on runs.csv beside it, the parts of N shards copied
//! into one directory never collide, and DuckDB or polars read every shard as one dataset
//! with a glob (`read_parquet('x-shard-*/runs.parquet/*.parquet')`).
//!
//! A whole sweep's file (and a merge's) is written from its records; a larger one's and a
//! shard's from its record stream, one row group at a time, gathered as plain integers
//! per column (about 9 bytes a cell), so a writer never holds records.

use std::collections::HashMap;
use std::io::{BufRead, Write};
use std::path::Path;
use std::sync::Arc;

use ::parquet::basic::{Compression, LogicalType, Repetition, Type as PhysicalType};
use ::parquet::data_type::{BoolType, ByteArray, ByteArrayType, DoubleType, Int64Type};
use ::parquet::file::metadata::KeyValue;
use ::parquet::file::properties::{EnabledStatistics, WriterProperties};
use ::parquet::file::writer::SerializedFileWriter;
use ::parquet::schema::types::Type;

use crate::config::Experiment;
use crate::output::{
    fixed_cell, sometimes_cell, Cell, StreamedFile, TableColumns, FIXED_COLUMNS, SETUP_MS, TIME_MS,
};
use crate::provenance::Provenance;
use crate::record::RunRecord;
use crate::shard::Shard;
use crate::stream::StreamReader;
use crate::RunnerError;

/// The dataset directory of a results directory (and of a shard's): its Parquet files.
pub const PARQUET_DIR: &str = "runs.parquet";

/// Runs that do not fit the Parquet dataset's columns as gathered: a bug in the writer,
/// never the user's input ([`RunnerError::Columns`]).
#[derive(Debug, thiserror::Error)]
pub enum ColumnsError {
    /// A run with a counter outside the columns chosen from the runs.
    #[error("{PARQUET_DIR}: run {problem} of {planner} on {map} has a counter `{name}` the file's columns lack")]
    Counter {
        /// The run's problem.
        problem: usize,
        /// The run's planner label.
        planner: String,
        /// The run's map.
        map: String,
        /// The counter.
        name: String,
    },
    /// A column or text (its kind and index) missing from the gathered row group.
    #[error("{PARQUET_DIR}: {0} {1} was not gathered")]
    NotGathered(&'static str, usize),
}

/// The name of shard `shard`'s file in [`PARQUET_DIR`]: `part-K-of-N.parquet`
/// (`part-1-of-1.parquet` for a whole sweep).
pub fn part_name(shard: Shard) -> String {
    format!("part-{}-of-{}.parquet", shard.index, shard.count)
}

/// The path of shard `shard`'s file relative to its results directory.
pub fn part_path(shard: Shard) -> std::path::PathBuf {
    std::path::Path::new(PARQUET_DIR).join(part_name(shard))
}

/// The most runs in one row group: the rows a writer gathers at once (as plain integers,
/// about 9 bytes a cell), and the unit a reader skips or reads in parallel.
///
/// The writer keeps each row group's footer entry (its column chunks' metadata and
/// statistics, about 21 KB for runs.csv's columns, measured with heaptrack) until the file
/// closes, so the rows per group set how a file's writer grows with its runs: at 131,072
/// runs a group, 10 million runs hold about 1.6 MB of footer (issue 29).
pub const ROW_GROUP_ROWS: usize = 131_072;

/// The most values handed to the column writer at once: it encodes and compresses pages
/// as they fill, so its buffers stay at a few pages whatever [`ROW_GROUP_ROWS`] is.
const WRITE_BATCH_ROWS: usize = 8_192;

/// The key-value metadata keys (each value is text; the JSON ones are JSON objects).
pub mod keys {
    /// The experiment's name.
    pub const EXPERIMENT: &str = "gridplan.experiment";
    /// The config file's path, as runs.json's `config`.
    pub const CONFIG: &str = "gridplan.config";
    /// The config file's text, when it still hashes to the provenance's `config_sha256`.
    pub const CONFIG_TEXT: &str = "gridplan.config_toml";
    /// The sweep's provenance (version, commit, date, host, CPU, threads, config hash), JSON.
    pub const PROVENANCE: &str = "gridplan.provenance";
    /// Every label's planner, resolved parameters and budget, JSON (runs.json's `planners`).
    pub const PLANNERS: &str = "gridplan.planners";
    /// The shard a shard's file holds (`k/n`); absent in a whole sweep's file.
    pub const SHARD: &str = "gridplan.shard";
}

/// What goes into the file's key-value metadata besides the rows.
#[derive(Clone, Copy)]
pub struct Header<'a> {
    /// The experiment.
    pub experiment: &'a Experiment,
    /// The sweep's provenance, if collected.
    pub provenance: Option<&'a Provenance>,
    /// The shard, for a shard's file (`None`: a whole sweep's or a merge's).
    pub shard: Option<Shard>,
}

/// The physical and logical type of a column.
#[derive(Clone, Copy)]
enum Kind {
    /// UTF-8 text (BYTE_ARRAY, logical String).
    Text,
    /// An unsigned integer (INT64, logical UINT64).
    Unsigned,
    /// A float (DOUBLE).
    Float,
    /// A boolean (BOOLEAN).
    Boolean,
}

/// The [`FIXED_COLUMNS`]' kinds and whether each may be empty, in order.
const FIXED_KINDS: [(Kind, bool); 21] = [
    (Kind::Text, false),     // map
    (Kind::Unsigned, false), // problem
    (Kind::Unsigned, false), // start_x
    (Kind::Unsigned, false), // start_y
    (Kind::Unsigned, false), // goal_x
    (Kind::Unsigned, false), // goal_y
    (Kind::Text, false),     // planner
    (Kind::Text, false),     // algorithm
    (Kind::Unsigned, false), // repeat
    (Kind::Unsigned, true),  // seed
    (Kind::Text, false),     // status
    (Kind::Unsigned, true),  // steps
    (Kind::Unsigned, true),  // turns
    (Kind::Unsigned, true),  // score
    (Kind::Float, true),     // length
    (Kind::Float, true),     // optimal_length
    (Kind::Boolean, true),   // valid
    // The measurements are null for an invalid problem, which was not run.
    (Kind::Float, true),    // time_ms
    (Kind::Float, true),    // setup_ms
    (Kind::Unsigned, true), // peak_heap_bytes
    (Kind::Unsigned, true), // bucket
];

/// `ms` rounded to the nanosecond (runs.json's rounding).
fn nanoseconds(ms: f64) -> f64 {
    (ms * 1e6).round() / 1e6
}

/// The kind of each column of a file with `columns`, and whether it may be empty: the
/// [`FIXED_COLUMNS`]', then the optional `error` (text) and `cost` (a float) when the
/// table has them, then one optional unsigned column per counter.
fn kinds(columns: &TableColumns) -> Vec<(Kind, bool)> {
    FIXED_KINDS
        .into_iter()
        .chain(columns.sometimes().map(|i| match i {
            0 => (Kind::Text, true),
            _ => (Kind::Float, true),
        }))
        .chain(columns.counters().iter().map(|_| (Kind::Unsigned, true)))
        .collect()
}

/// The file's schema: runs.csv's columns ([`TableColumns::names`]) of the [`kinds`].
fn schema(columns: &TableColumns) -> Result<Type, RunnerError> {
    let column = |name: &str, kind: Kind, optional: bool| {
        let (physical, logical) = match kind {
            Kind::Text => (PhysicalType::BYTE_ARRAY, Some(LogicalType::String)),
            Kind::Unsigned => (PhysicalType::INT64, Some(LogicalType::integer(64, false))),
            Kind::Float => (PhysicalType::DOUBLE, None),
            Kind::Boolean => (PhysicalType::BOOLEAN, None),
        };
        Type::primitive_type_builder(name, physical)
            .with_logical_type(logical)
            .with_repetition(if optional {
                Repetition::OPTIONAL
            } else {
                Repetition::REQUIRED
            })
            .build()
            .map(Arc::new)
    };
    let mut fields = Vec::new();
    for (name, (kind, optional)) in columns.names().into_iter().zip(kinds(columns)) {
        fields.push(column(name, kind, optional)?);
    }
    Ok(Type::group_type_builder("runs")
        .with_fields(fields)
        .build()?)
}

/// The key-value metadata of `header`.
fn metadata(header: &Header<'_>) -> Result<Vec<KeyValue>, RunnerError> {
    let experiment = header.experiment;
    let mut kv = vec![
        KeyValue::new(keys::EXPERIMENT.into(), experiment.name.clone()),
        KeyValue::new(keys::CONFIG.into(), experiment.source.display().to_string()),
    ];
    if let Some(provenance) = header.provenance {
        kv.push(KeyValue::new(
            keys::PROVENANCE.into(),
            serde_json::to_string(provenance).map_err(RunnerError::Json)?,
        ));
        // The text that ran, only if the file is unchanged since (same SHA-256).
        if let (Some(hash), Ok(text)) = (
            &provenance.config_sha256,
            std::fs::read_to_string(&experiment.source),
        ) {
            if &crate::provenance::sha256_hex(text.as_bytes()) == hash {
                kv.push(KeyValue::new(keys::CONFIG_TEXT.into(), text));
            }
        }
    }
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
    kv.push(KeyValue::new(
        keys::PLANNERS.into(),
        serde_json::to_string(&planners).map_err(RunnerError::Json)?,
    ));
    if let Some(shard) = header.shard {
        kv.push(KeyValue::new(
            keys::SHARD.into(),
            format!("{}/{}", shard.index, shard.count),
        ));
    }
    Ok(kv)
}

/// One column of a row group being gathered: whether each row has a value, and the
/// values present as 64 bits (a text's id in [`Group::texts`], an integer, a float's bits,
/// a boolean as 0 or 1).
#[derive(Default)]
struct GroupColumn {
    present: Vec<bool>,
    values: Vec<u64>,
}

/// A row group being gathered, column by column, as plain integers: about 9 bytes per
/// cell, reused from one group to the next, so a writer holds no records.
#[derive(Default)]
struct Group {
    columns: Vec<GroupColumn>,
    /// The distinct texts of the group's text columns (maps, labels, algorithms,
    /// statuses), each once.
    texts: Vec<ByteArray>,
    /// Each of `texts`' index, so that a row finds its texts' ids by hashing, not by a
    /// scan of every map name (a sweep of many maps has hundreds).
    text_ids: HashMap<String, u64>,
    rows: usize,
}

impl Group {
    /// Adds `r`'s row in the file's `columns` (a counter outside them is an error, never
    /// dropped silently).
    fn push(&mut self, r: &RunRecord, columns: &TableColumns) -> Result<(), RunnerError> {
        let counters = columns.counters();
        if let Some((name, _)) = r
            .counters
            .iter()
            .find(|(name, _)| !counters.iter().any(|c| c == name))
        {
            return Err(RunnerError::Columns(ColumnsError::Counter {
                problem: r.problem,
                planner: r.planner.clone(),
                map: r.map.clone(),
                name: name.to_string(),
            }));
        }
        let fixed = (0..FIXED_COLUMNS.len()).map(|index| match fixed_cell(r, index) {
            // Times are rounded to the nanosecond, as in runs.json.
            Cell::Float(v) if matches!(index, TIME_MS | SETUP_MS) => {
                Cell::Float(v.map(nanoseconds))
            }
            cell => cell,
        });
        let cells = fixed
            .chain(columns.sometimes().map(|i| sometimes_cell(r, i)))
            .chain(counters.iter().map(|c| Cell::Unsigned(r.counters.get(c))));
        let n_columns = FIXED_COLUMNS.len() + columns.sometimes().count() + counters.len();
        self.columns.resize_with(n_columns, GroupColumn::default);
        for (column, cell) in self.columns.iter_mut().zip(cells) {
            let value = match cell {
                Cell::Text(None) => None,
                Cell::Text(Some(text)) => Some(match self.text_ids.get(text) {
                    Some(&id) => id,
                    None => {
                        let id = self.texts.len() as u64;
                        self.texts.push(ByteArray::from(text));
                        self.text_ids.insert(text.to_string(), id);
                        id
                    }
                }),
                Cell::Unsigned(v) => v,
                Cell::Float(v) => v.map(f64::to_bits),
                Cell::Boolean(v) => v.map(u64::from),
            };
            column.present.push(value.is_some());
            column.values.extend(value);
        }
        self.rows += 1;
        Ok(())
    }

    fn clear(&mut self) {
        for column in &mut self.columns {
            column.present.clear();
            column.values.clear();
        }
        self.texts.clear();
        self.text_ids.clear();
        self.rows = 0;
    }
}

/// A runs.parquet being written, one row group per [`ROW_GROUP_ROWS`] rows pushed.
pub struct RunsWriter<W: Write + Send> {
    writer: SerializedFileWriter<W>,
    columns: TableColumns,
    /// Each column's kind and whether it may be empty ([`kinds`]).
    kinds: Vec<(Kind, bool)>,
    group: Group,
    // Reused per column: definition levels and values.
    levels: Vec<i16>,
    texts: Vec<ByteArray>,
    unsigned: Vec<i64>,
    floats: Vec<f64>,
    booleans: Vec<bool>,
}

impl<W: Write + Send> RunsWriter<W> {
    /// Starts a file on `out` with `columns` beyond the fixed ones (a record's counter
    /// outside them is an error, never dropped silently).
    pub fn new(out: W, columns: TableColumns, header: &Header<'_>) -> Result<Self, RunnerError> {
        let properties = WriterProperties::builder()
            .set_compression(Compression::SNAPPY)
            .set_max_row_group_row_count(Some(ROW_GROUP_ROWS))
            // Statistics per column chunk (min, max, null count: what DuckDB and pandas
            // use to skip row groups), not per page, and no offset index: the page-level
            // entries are held for every row group until the footer is written, and a
            // reader of whole columns has no use for them.
            .set_statistics_enabled(EnabledStatistics::Chunk)
            .set_offset_index_disabled(true)
            .set_key_value_metadata(Some(metadata(header)?))
            .set_created_by(format!("gridplan {}", env!("CARGO_PKG_VERSION")))
            .build();
        let writer =
            SerializedFileWriter::new(out, Arc::new(schema(&columns)?), Arc::new(properties))?;
        Ok(RunsWriter {
            writer,
            kinds: kinds(&columns),
            columns,
            group: Group::default(),
            levels: Vec::new(),
            texts: Vec::new(),
            unsigned: Vec::new(),
            floats: Vec::new(),
            booleans: Vec::new(),
        })
    }

    /// Adds `record`'s row; a row group is written every [`ROW_GROUP_ROWS`] rows.
    pub fn push(&mut self, record: &RunRecord) -> Result<(), RunnerError> {
        self.group.push(record, &self.columns)?;
        if self.group.rows == ROW_GROUP_ROWS {
            self.write_group()?;
        }
        Ok(())
    }

    /// Writes the rows gathered as one row group (nothing if none).
    fn write_group(&mut self) -> Result<(), RunnerError> {
        if self.group.rows == 0 {
            return Ok(());
        }
        let mut group = self.writer.next_row_group()?;
        let mut index = 0;
        while let Some(mut column) = group.next_column()? {
            self.levels.clear();
            self.texts.clear();
            self.unsigned.clear();
            self.floats.clear();
            self.booleans.clear();
            let (kind, optional) = *self
                .kinds
                .get(index)
                .ok_or_else(|| RunnerError::Columns(ColumnsError::NotGathered("column", index)))?;
            let gathered =
                self.group.columns.get(index).ok_or_else(|| {
                    RunnerError::Columns(ColumnsError::NotGathered("column", index))
                })?;
            self.levels
                .extend(gathered.present.iter().map(|&p| i16::from(p)));
            let values = gathered.values.iter().copied();
            match kind {
                Kind::Text => {
                    for id in values {
                        let text = self.group.texts.get(id as usize).ok_or_else(|| {
                            RunnerError::Columns(ColumnsError::NotGathered("text", id as usize))
                        })?;
                        self.texts.push(text.clone());
                    }
                }
                // A UINT64 is stored in INT64's bits (the Parquet format's rule).
                Kind::Unsigned => self.unsigned.extend(values.map(|v| v as i64)),
                Kind::Float => self.floats.extend(values.map(f64::from_bits)),
                Kind::Boolean => self.booleans.extend(values.map(|v| v != 0)),
            }
            // Values and levels go to the column writer in batches of WRITE_BATCH_ROWS rows
            // (a batch's values are those of its present rows).
            let mut value_start = 0;
            for levels in self.levels.chunks(WRITE_BATCH_ROWS) {
                let n_values = levels.iter().filter(|&&l| l != 0).count();
                let range = value_start..value_start + n_values;
                value_start += n_values;
                let levels = optional.then_some(levels);
                match kind {
                    Kind::Text => {
                        column.typed::<ByteArrayType>().write_batch(
                            &self.texts[range],
                            levels,
                            None,
                        )?;
                    }
                    Kind::Unsigned => {
                        column.typed::<Int64Type>().write_batch(
                            &self.unsigned[range],
                            levels,
                            None,
                        )?;
                    }
                    Kind::Float => {
                        column.typed::<DoubleType>().write_batch(
                            &self.floats[range],
                            levels,
                            None,
                        )?;
                    }
                    Kind::Boolean => {
                        column.typed::<BoolType>().write_batch(
                            &self.booleans[range],
                            levels,
                            None,
                        )?;
                    }
                }
            }
            column.close()?;
            index += 1;
        }
        group.close()?;
        self.group.clear();
        Ok(())
    }

    /// Writes the last row group and the footer (schema, row group index, key-value
    /// metadata).
    pub fn close(mut self) -> Result<(), RunnerError> {
        self.write_group()?;
        self.writer.close()?;
        Ok(())
    }
}

/// Writes `records` (a whole sweep's, in run order) as runs.parquet to `out`, in row
/// groups of [`ROW_GROUP_ROWS`]; the columns are runs.csv's ([`TableColumns`]).
pub fn write_runs_parquet(
    out: &mut (dyn Write + Send),
    header: &Header<'_>,
    records: &[RunRecord],
) -> Result<(), RunnerError> {
    let mut columns = TableColumns::default();
    for record in records {
        columns.add(record);
    }
    let mut writer = RunsWriter::new(out, columns, header)?;
    for record in records {
        writer.push(record)?;
    }
    writer.close()
}

/// Writes the records of a record stream (a shard's) as a Parquet file to `out`, holding
/// one row group of [`ROW_GROUP_ROWS`] rows as plain integers and no records: `open`
/// opens the stream, which is read twice (first for the columns, then for the rows).
pub fn write_stream_parquet<R: BufRead>(
    out: &mut (dyn Write + Send),
    header: &Header<'_>,
    open: impl Fn() -> Result<R, RunnerError>,
    what: &str,
) -> Result<(), RunnerError> {
    let mut columns = TableColumns::default();
    let (_, mut reader) = StreamReader::new(open()?, what)?;
    while let Some((_, record)) = reader.next_run()? {
        columns.add(&record);
    }
    let mut writer = RunsWriter::new(out, columns, header)?;
    let (_, mut reader) = StreamReader::new(open()?, what)?;
    while let Some((_, record)) = reader.next_run()? {
        writer.push(&record)?;
    }
    writer.close()
}

/// The results file of a whole sweep's (or a merge's) Parquet part, written from its
/// `records` (in run order).
pub fn records_part<'a>(
    experiment: &'a Experiment,
    provenance: &'a Provenance,
    records: &'a [RunRecord],
) -> StreamedFile<'a> {
    StreamedFile {
        path: part_path(Shard::ALL),
        write: Box::new(move |out| {
            let header = Header {
                experiment,
                provenance: Some(provenance),
                shard: None,
            };
            write_runs_parquet(out, &header, records)
        }),
    }
}

/// The results file of a shard's Parquet part, written from its record stream `path`
/// (read twice, one row group at a time: [`write_stream_parquet`]).
pub fn stream_part<'a>(header: Header<'a>, path: &'a Path) -> StreamedFile<'a> {
    let shard = header.shard.unwrap_or(Shard::ALL);
    StreamedFile {
        path: part_path(shard),
        write: Box::new(move |out| {
            let open = || {
                crate::stream::open_regular(path)
                    .map(std::io::BufReader::new)
                    .map_err(|e| RunnerError::io(path, e))
            };
            write_stream_parquet(out, &header, open, &path.display().to_string())
        }),
    }
}
