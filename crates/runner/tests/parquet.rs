//! The Parquet dataset runs.parquet/ (issue 29), read back with the `parquet` crate's own
//! reader: its rows are runs.csv's, typed; a sharded sweep's per-shard parts hold the
//! merged part's rows; its row groups are bounded; `outputs = [...]` chooses the tables;
//! and a refused output directory gets no Parquet file either.

use std::collections::BTreeMap;
use std::fs::File;
use std::path::{Path, PathBuf};

use parquet::basic::{Compression, LogicalType, Type as PhysicalType};
use parquet::file::reader::{FileReader, SerializedFileReader};
use parquet::record::Field;
use planner_runner::columnar::{self, keys, part_path, PARQUET_DIR, ROW_GROUP_ROWS};
use planner_runner::config::ConfigError;
use planner_runner::output::OutputFile;
use planner_runner::record::Reproduction;
use planner_runner::shard::Shard;
use planner_runner::sweep::{self, Render, Results, SweepArgs};
use planner_runner::{Experiment, RunnerError};

/// A report step that writes no report file (the runner's tables are under test here).
struct NoReport;

impl Render for NoReport {
    fn check(&self, _: &Experiment) -> Result<(), ConfigError> {
        Ok(())
    }

    fn render(&self, _: &Results<'_>) -> Result<(Vec<OutputFile>, Reproduction), RunnerError> {
        Ok((Vec::new(), Reproduction::default()))
    }
}

/// A whole sweep's Parquet file in its results directory `dir`.
fn whole(dir: &Path) -> PathBuf {
    dir.join(part_path(Shard::ALL))
}

/// A scratch directory for one test, removed first if a previous run left it.
fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("gridplan-parquet-{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A config with every kind of cell runs.csv has: Moving AI scenarios (buckets, optimal
/// lengths), a seeded planner (seed), PA-star (its own counters, so other planners' rows
/// have empty counter cells), BFS, and an invalid problem (a start on a wall: empty
/// steps, length and validity, and its `error`, a text with commas).
fn config(dir: &Path) -> PathBuf {
    config_with(dir, "")
}

/// [`config`] with `top` (top-level keys) added.
fn config_with(dir: &Path, top: &str) -> PathBuf {
    let maps = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../maps");
    std::fs::write(
        dir.join("wall.map"),
        "type octile\nheight 3\nwidth 6\nmap\n..@...\n..@...\n......\n",
    )
    .unwrap();
    let text = format!(
        "name = \"pq\"\nrepeats = 2\n{top}\n\
         [[maps]]\nfiles = [{arena:?}]\nscen = {scen:?}\nevery = 40\n\
         [[maps]]\nfiles = [\"wall.map\"]\npairs = [{{ start = [0, 0], goal = [5, 0] }}, {{ start = [2, 0], goal = [5, 0] }}]\n\
         [planners.astar]\nplanner = \"astar\"\n\
         [planners.bfs]\nplanner = \"bfs\"\n\
         [planners.pastar]\nplanner = \"pastar\"\n\
         [planners.rrt]\nplanner = \"rrt\"\n",
        arena = maps.join("movingai/arena.map").display().to_string(),
        scen = maps.join("movingai/arena.map.scen").display().to_string(),
    );
    let path = dir.join("pq.toml");
    std::fs::write(&path, text).unwrap();
    path
}

/// The file's rows, each cell as runs.csv writes it (floats by `csv_float`, empty for
/// null), with the column names.
fn rows_as_csv(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let reader = SerializedFileReader::new(File::open(path).unwrap()).unwrap();
    let columns: Vec<String> = reader
        .metadata()
        .file_metadata()
        .schema_descr()
        .columns()
        .iter()
        .map(|c| c.name().to_string())
        .collect();
    let mut rows = Vec::new();
    for row in reader.get_row_iter(None).unwrap() {
        let row = row.unwrap();
        let cells = row
            .get_column_iter()
            .map(|(_, field)| match field {
                Field::Null => String::new(),
                Field::Bool(b) => b.to_string(),
                Field::ULong(v) => v.to_string(),
                Field::Double(v) => planner_runner::output::csv_float(*v),
                Field::Str(s) => s.clone(),
                other => panic!("unexpected field {other:?}"),
            })
            .collect();
        rows.push(cells);
    }
    (columns, rows)
}

/// runs.csv's header and rows (no cell of these configs holds a line break; a cell with a
/// comma is quoted, RFC 4180's `""` for a quote).
fn csv_rows(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let split = |line: &str| {
        let (mut cells, mut cell, mut quoted) = (Vec::new(), String::new(), false);
        let mut chars = line.chars().peekable();
        while let Some(c) = chars.next() {
            match c {
                '"' if quoted && chars.peek() == Some(&'"') => {
                    chars.next();
                    cell.push('"');
                }
                '"' => quoted = !quoted,
                ',' if !quoted => cells.push(std::mem::take(&mut cell)),
                c => cell.push(c),
            }
        }
        cells.push(cell);
        cells
    };
    let mut lines = text.lines().map(split);
    let header = lines.next().unwrap();
    (header, lines.collect())
}

/// Asserts that two tables are equal cell for cell (floats included: both tables hold
/// the same doubles, times rounded to the nanosecond in each).
fn assert_same_table(csv: &[Vec<String>], parquet: &[Vec<String>], columns: &[String]) {
    assert_eq!(csv.len(), parquet.len());
    for (n, (a, b)) in csv.iter().zip(parquet).enumerate() {
        assert_eq!(a.len(), b.len(), "row {n}");
        for ((x, y), name) in a.iter().zip(b).zip(columns) {
            assert_eq!(x, y, "row {n} column {name}");
        }
    }
}

/// A scratch directory `name`, [`config`]'s file in it and the results directory its
/// sweep wrote on two threads.
fn swept(name: &str) -> (PathBuf, PathBuf, PathBuf) {
    let dir = scratch(name);
    let config = config(&dir);
    let out = dir.join("results");
    let mut args = SweepArgs::new(&config, &NoReport);
    args.output = Some(&out);
    args.threads = 2;
    sweep::experiment(&args).unwrap();
    (dir, config, out)
}

#[test]
fn the_parquet_rows_are_the_csv_rows_typed_with_the_metadata() {
    let (dir, config, out) = swept("rows");
    let (csv_header, csv) = csv_rows(&out.join("runs.csv"));
    // The dataset directory holds the one part.
    let parts: Vec<String> = std::fs::read_dir(out.join(PARQUET_DIR))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(parts, ["part-1-of-1.parquet"]);
    let (columns, rows) = rows_as_csv(&whole(&out));
    assert_eq!(columns, csv_header);
    assert_same_table(&csv, &rows, &columns);
    // 4 planners x (4 scenarios and 1 valid pair, 2 repeats each; the invalid pair once).
    assert_eq!(rows.len(), 4 * (5 * 2 + 1));
    let at = |name: &str| columns.iter().position(|c| c == name).unwrap();
    // Every kind of empty cell occurs, and every kind of value.
    assert!(rows.iter().any(|r| r[at("status")] == "invalid_problem"
        && r[at("steps")].is_empty()
        && r[at("valid")].is_empty()));
    assert!(rows.iter().any(|r| !r[at("seed")].is_empty()));
    assert!(rows.iter().any(|r| r[at("seed")].is_empty()));
    assert!(rows.iter().any(|r| !r[at("bucket")].is_empty()));
    assert!(rows.iter().any(|r| r[at("valid")] == "true"));
    // The invalid problem's error follows the fixed columns; other runs have none.
    assert_eq!(at("error"), 21);
    assert!(rows
        .iter()
        .any(|r| r[at("error")] == "start (2, 0) is blocked"));
    assert!(rows.iter().any(|r| r[at("error")].is_empty()));
    assert!(!columns.contains(&"cost".to_string()), "no weighted map");
    // A counter column that some planners leave empty and others fill.
    assert!((22..columns.len())
        .any(|c| rows.iter().any(|r| r[c].is_empty()) && rows.iter().any(|r| !r[c].is_empty())));

    let reader = SerializedFileReader::new(File::open(whole(&out)).unwrap()).unwrap();
    let meta = reader.metadata();
    let schema = meta.file_metadata().schema_descr();
    let kind = |name: &str| {
        let c = schema.column(at(name));
        (c.physical_type(), c.logical_type_ref().cloned())
    };
    let unsigned = Some(LogicalType::integer(64, false));
    assert_eq!(
        kind("map"),
        (PhysicalType::BYTE_ARRAY, Some(LogicalType::String))
    );
    assert_eq!(kind("problem"), (PhysicalType::INT64, unsigned.clone()));
    assert_eq!(kind("n_expanded"), (PhysicalType::INT64, unsigned));
    assert_eq!(kind("length"), (PhysicalType::DOUBLE, None));
    assert_eq!(kind("valid"), (PhysicalType::BOOLEAN, None));
    assert_eq!(
        kind("error"),
        (PhysicalType::BYTE_ARRAY, Some(LogicalType::String))
    );
    for group in meta.row_groups() {
        for column in group.columns() {
            assert_eq!(column.compression(), Compression::SNAPPY);
        }
    }
    let kv: BTreeMap<&str, &str> = meta
        .file_metadata()
        .key_value_metadata()
        .unwrap()
        .iter()
        .map(|kv| (kv.key.as_str(), kv.value.as_deref().unwrap_or("")))
        .collect();
    assert_eq!(kv[keys::EXPERIMENT], "pq");
    assert_eq!(
        kv[keys::CONFIG_TEXT],
        std::fs::read_to_string(&config).unwrap()
    );
    let planners: serde_json::Value = serde_json::from_str(kv[keys::PLANNERS]).unwrap();
    assert_eq!(planners["rrt"]["planner"], "rrt");
    let provenance: serde_json::Value = serde_json::from_str(kv[keys::PROVENANCE]).unwrap();
    assert_eq!(provenance["threads"], 2);
    assert!(!kv.contains_key(keys::SHARD));
    // The same header as runs.json's.
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("runs.json")).unwrap()).unwrap();
    assert_eq!(json["planners"], planners);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// runs.csv's floats read back as the very doubles of runs.json and runs.parquet (a
/// length was rounded to 6 decimals, so equal CSV costs could differ in Parquet), and an
/// invalid problem, never run, has no time, setup time or peak heap in any table (they
/// were 0, which a mean counts), Parquet's columns nullable for it.
#[test]
fn csv_floats_are_the_json_doubles_and_an_invalid_problem_has_no_measurements() {
    let (dir, _, out) = swept("floats");
    let (columns, csv) = csv_rows(&out.join("runs.csv"));
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("runs.json")).unwrap()).unwrap();
    let json_columns: Vec<&str> = json["runs"]["columns"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c.as_str().unwrap())
        .collect();
    let data = json["runs"]["data"].as_array().unwrap();
    assert_eq!(data.len(), csv.len());
    let at = |name: &str| columns.iter().position(|c| c == name).unwrap();
    let json_at = |name: &str| json_columns.iter().position(|&c| c == name).unwrap();
    let mut inexact = 0;
    for (row, json_row) in csv.iter().zip(data) {
        for name in ["length", "optimal_length", "time_ms", "setup_ms"] {
            let (cell, value) = (&row[at(name)], &json_row[json_at(name)]);
            if cell.is_empty() {
                assert!(value.is_null(), "{name}: {value}");
                continue;
            }
            let read: f64 = cell.parse().unwrap();
            let want = value.as_f64().unwrap();
            assert_eq!(read.to_bits(), want.to_bits(), "{name}: {cell} {want}");
            inexact += usize::from(format!("{want:.6}").parse::<f64>().unwrap() != want);
        }
        let invalid = row[at("status")] == "invalid_problem";
        for name in ["time_ms", "setup_ms", "peak_heap_bytes"] {
            assert_eq!(row[at(name)].is_empty(), invalid, "{name} {row:?}");
            assert_eq!(json_row[json_at(name)].is_null(), invalid, "{name}");
        }
    }
    // Some value has more digits than 6 decimals keep (an octile length).
    assert!(inexact > 0);
    let (parquet_columns, rows) = rows_as_csv(&whole(&out));
    assert_eq!(parquet_columns, columns);
    assert_same_table(&csv, &rows, &columns);
    assert!(rows.iter().any(|r| r[at("status")] == "invalid_problem"));
    let reader = SerializedFileReader::new(File::open(whole(&out)).unwrap()).unwrap();
    let meta = reader.metadata();
    let schema = meta.file_metadata().schema_descr();
    for name in ["time_ms", "setup_ms", "peak_heap_bytes"] {
        assert!(schema.column(at(name)).self_type().is_optional(), "{name}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn shard_files_hold_the_merged_rows() {
    let dir = scratch("shards");
    let config = config(&dir);
    let mut shard_dirs = Vec::new();
    for k in 1..=3 {
        let out = dir.join(format!("shard-{k}"));
        let mut args = SweepArgs::new(&config, &NoReport);
        args.output = Some(&out);
        args.threads = 2;
        args.shard = Some(Shard::new(k, 3).unwrap());
        sweep::experiment(&args).unwrap();
        shard_dirs.push(out);
    }
    let merged = dir.join("merged");
    sweep::merge(&shard_dirs, Some(&merged), None, &NoReport, &|_| {
        planner_runner::provenance::Machine::default()
    })
    .unwrap();
    let (columns, merged_rows) = rows_as_csv(&whole(&merged));
    let (_, csv) = csv_rows(&merged.join("runs.csv"));
    assert_same_table(&csv, &merged_rows, &columns);
    // The shards' rows, keyed by (map, problem, planner, repeat), equal the merged rows
    // (timing and memory aside: those columns are measurements).
    let key = |r: &Vec<String>| (r[0].clone(), r[1].clone(), r[6].clone(), r[8].clone());
    let measured = ["time_ms", "setup_ms", "peak_heap_bytes"]
        .map(|name| columns.iter().position(|c| c == name).unwrap());
    let strip = |r: &Vec<String>| -> Vec<String> {
        r.iter()
            .enumerate()
            .map(|(i, c)| {
                if measured.contains(&i) {
                    String::new()
                } else {
                    c.clone()
                }
            })
            .collect()
    };
    let mut from_shards = BTreeMap::new();
    for (k, shard) in shard_dirs.iter().enumerate() {
        let path = shard.join(part_path(Shard::new(k as u64 + 1, 3).unwrap()));
        let (shard_columns, rows) = rows_as_csv(&path);
        // The same columns; the counters' order is that of first appearance in the
        // shard, so a shard's may differ, and `error` is there only when a run of the
        // shard has one (Parquet readers match columns by name).
        assert_eq!(shard_columns[..21], columns[..21]);
        let mut sorted = shard_columns.clone();
        sorted.sort();
        let mut expected = columns.clone();
        expected.retain(|c| c != "error" || shard_columns.contains(c));
        expected.sort();
        assert_eq!(sorted, expected);
        let order: Vec<Option<usize>> = columns
            .iter()
            .map(|c| shard_columns.iter().position(|s| s == c))
            .collect();
        assert!(!rows.is_empty());
        for row in rows {
            let row: Vec<String> = order
                .iter()
                .map(|&i| i.map_or_else(String::new, |i| row[i].clone()))
                .collect();
            assert!(from_shards.insert(key(&row), strip(&row)).is_none());
        }
        let reader = SerializedFileReader::new(File::open(&path).unwrap()).unwrap();
        let kv = reader
            .metadata()
            .file_metadata()
            .key_value_metadata()
            .unwrap();
        let shard_kv = kv.iter().find(|kv| kv.key == keys::SHARD).unwrap();
        assert_eq!(
            shard_kv.value.as_deref(),
            Some(format!("{}/3", k + 1).as_str())
        );
    }
    let merged_map: BTreeMap<_, _> = merged_rows.iter().map(|r| (key(r), strip(r))).collect();
    assert_eq!(merged_map.len(), merged_rows.len());
    assert_eq!(from_shards, merged_map);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// More runs than a row group holds: the file has the bounded groups, in order.
#[test]
fn row_groups_are_bounded() {
    let dir = scratch("groups");
    let config = config(&dir);
    let experiment = planner_runner::config::load(&config).unwrap();
    let one = planner_runner::run_all(&experiment, &planner_runner::RunOptions::default()).unwrap();
    let n = 2 * ROW_GROUP_ROWS + 7;
    let records: Vec<_> = one.iter().cycle().take(n).cloned().collect();
    let path = dir.join("groups.parquet");
    let mut file = std::io::BufWriter::new(File::create(&path).unwrap());
    let header = columnar::Header {
        experiment: &experiment,
        provenance: None,
        shard: None,
    };
    columnar::write_runs_parquet(&mut file, &header, &records).unwrap();
    drop(file);
    let reader = SerializedFileReader::new(File::open(&path).unwrap()).unwrap();
    let sizes: Vec<i64> = reader
        .metadata()
        .row_groups()
        .iter()
        .map(|g| g.num_rows())
        .collect();
    let full = ROW_GROUP_ROWS as i64;
    assert_eq!(sizes, [full, full, 7]);
    // The last row is the last record's.
    let last = reader.get_row_iter(None).unwrap().last().unwrap().unwrap();
    let record = &records[n - 1];
    let field = |name: &str| {
        last.get_column_iter()
            .find(|(c, _)| c.as_str() == name)
            .map(|(_, f)| f.clone())
            .unwrap()
    };
    assert_eq!(field("map"), Field::Str(record.map.clone()));
    assert_eq!(field("problem"), Field::ULong(record.problem as u64));
    assert_eq!(field("repeat"), Field::ULong(u64::from(record.repeat)));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// An output path the results rules refuse (a regular file; an unmarked directory with
/// files in it) is refused before runs.parquet is written, as for the other files.
#[test]
fn refused_outputs_get_no_parquet() {
    let dir = scratch("refused");
    let config = config(&dir);
    let file = dir.join("a-file");
    std::fs::write(&file, "mine").unwrap();
    let foreign = dir.join("foreign");
    std::fs::create_dir(&foreign).unwrap();
    std::fs::write(foreign.join("notes.txt"), "mine").unwrap();
    for out in [&file, &foreign] {
        let mut args = SweepArgs::new(&config, &NoReport);
        args.output = Some(out);
        let error = sweep::experiment(&args).unwrap_err();
        assert!(matches!(error, RunnerError::Output(_)), "{error}");
    }
    assert_eq!(std::fs::read_to_string(&file).unwrap(), "mine");
    let names: Vec<String> = std::fs::read_dir(&foreign)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, ["notes.txt"]);
    // Nowhere under the scratch directory is there a Parquet dataset or file.
    fn any_parquet(dir: &Path) -> bool {
        std::fs::read_dir(dir).unwrap().any(|e| {
            let path = e.unwrap().path();
            path.file_name() == Some(PARQUET_DIR.as_ref())
                || path.extension() == Some("parquet".as_ref())
                || (path.is_dir() && !path.is_symlink() && any_parquet(&path))
        })
    }
    assert!(!any_parquet(&dir));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `outputs = [...]` chooses the tables: only the Parquet dataset (records.stream, which
/// `report` reads, stays); an empty list or an unknown table is refused at the key.
#[test]
fn outputs_choose_the_tables() {
    let dir = scratch("outputs");
    let config = config_with(&dir, "outputs = [\"parquet\"]");
    let out = dir.join("results");
    let mut args = SweepArgs::new(&config, &NoReport);
    args.output = Some(&out);
    sweep::experiment(&args).unwrap();
    assert!(whole(&out).is_file());
    assert!(out.join(sweep::RESULTS_RECORDS).is_file());
    assert!(!out.join("runs.csv").exists());
    assert!(!out.join("runs.json").exists());
    // A shard of it writes its part too, a shard of a csv-only sweep none.
    let shard = dir.join("shard");
    args.output = Some(&shard);
    args.shard = Some(Shard::new(2, 2).unwrap());
    sweep::experiment(&args).unwrap();
    assert!(shard.join(part_path(Shard::new(2, 2).unwrap())).is_file());
    let csv_only = config_with(&dir, "outputs = [\"csv\"]");
    let mut args = SweepArgs::new(&csv_only, &NoReport);
    let csv_out = dir.join("csv");
    args.output = Some(&csv_out);
    sweep::experiment(&args).unwrap();
    assert!(csv_out.join("runs.csv").is_file());
    assert!(!csv_out.join(PARQUET_DIR).exists());
    assert!(!csv_out.join("runs.json").exists());

    let refused = |top: &str, wanted: &str| {
        let config = config_with(&dir, top);
        let error = planner_runner::config::load(&config).unwrap_err();
        let text = error.to_string();
        assert_eq!(error.line, 3, "{text}");
        assert!(text.contains(wanted), "{text}");
    };
    refused("outputs = []", "key `outputs`: names no table");
    refused("outputs = [\"xlsx\"]", "xlsx");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// runs.csv and runs.parquet have runs.json's `error` (why a run was refused: a blocked
/// goal, a planner over `max_memory_mb`) and `cost` (a weighted map's path cost) when
/// some run has one; they had neither.
#[test]
fn errors_and_costs_are_in_every_table() {
    let dir = scratch("cost");
    std::fs::write(
        dir.join("swamp.map"),
        "type octile\nheight 3\nwidth 4\nmap\n.SS.\n.@S.\n....\n",
    )
    .unwrap();
    let config = dir.join("cost.toml");
    std::fs::write(
        &config,
        "name = \"cost\"\n[[maps]]\nfiles = [\"swamp.map\"]\ncosts = { swamp = 5 }\n\
         pairs = [{ start = [0, 0], goal = [3, 0] }, { start = [0, 0], goal = [1, 1] }]\n\
         [planners.astar]\nplanner = \"astar\"\n\
         [planners.small]\nplanner = \"astar\"\nbudget = { max_memory_mb = 0 }\n",
    )
    .unwrap();
    let out = dir.join("results");
    let mut args = SweepArgs::new(&config, &NoReport);
    args.output = Some(&out);
    sweep::experiment(&args).unwrap();
    let (header, csv) = csv_rows(&out.join("runs.csv"));
    assert_eq!(header[21..23], ["error", "cost"]);
    let (columns, parquet) = rows_as_csv(&whole(&out));
    assert_eq!(columns, header);
    assert_same_table(&csv, &parquet, &columns);
    // Each run's error and cost are runs.json's.
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("runs.json")).unwrap()).unwrap();
    let json_columns = json["runs"]["columns"].as_array().unwrap();
    let at = |name: &str| json_columns.iter().position(|c| c == name).unwrap();
    let data = json["runs"]["data"].as_array().unwrap();
    assert_eq!(data.len(), csv.len());
    for (row, json_row) in csv.iter().zip(data) {
        let error = json_row[at("error")].as_str().unwrap_or_default();
        assert_eq!(row[21], error);
        // The same double: runs.csv writes the shortest decimal that reads back as it.
        let cost = json_row[at("cost")].as_f64();
        assert_eq!(
            row[22].parse::<f64>().ok().map(f64::to_bits),
            cost.map(f64::to_bits)
        );
    }
    // A found path's cost, the blocked goal and the refused planner, each once at least.
    assert!(csv.iter().any(|r| !r[22].is_empty() && r[21].is_empty()));
    assert!(csv.iter().any(|r| r[21] == "goal (1, 1) is blocked"));
    assert!(csv
        .iter()
        .any(|r| r[6] == "small" && r[21].contains("max_memory_mb = 0")));
    let reader = SerializedFileReader::new(File::open(whole(&out)).unwrap()).unwrap();
    let schema = reader.metadata().file_metadata().schema_descr();
    assert_eq!(schema.column(22).physical_type(), PhysicalType::DOUBLE);
    std::fs::remove_dir_all(&dir).unwrap();
}
