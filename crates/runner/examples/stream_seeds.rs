//! Rewrites a stream file (a shard's `shard.stream`, framed) as the JSON Lines stream
//! that `StreamReader` also reads: its header with the JSON Lines format, then one
//! `{"run":INDEX,"record":RECORD}` line per run. `fuzz/run.sh` seeds the `stream` and
//! `frames` fuzz targets with it.
//!
//! Usage: `cargo run --release -p planner-runner --example stream_seeds -- IN OUT`.

use std::fs::File;
use std::io::{BufReader, BufWriter, Write};
use std::path::Path;
use std::process::ExitCode;

use planner_runner::stream::{encode, StreamReader, STREAM_FORMAT};
use planner_runner::RunnerError;

fn convert(input: &Path, output: &Path) -> Result<(), RunnerError> {
    let file = File::open(input).map_err(|e| RunnerError::io(input, e))?;
    let (mut header, mut reader) =
        StreamReader::new(BufReader::new(file), &input.display().to_string())?;
    header.format = STREAM_FORMAT;
    let mut out = header.to_line()?;
    while let Some((run, record)) = reader.next_run()? {
        encode(&mut out, run, &record)?;
    }
    let mut file = BufWriter::new(File::create(output).map_err(|e| RunnerError::io(output, e))?);
    file.write_all(&out)
        .and_then(|()| file.flush())
        .map_err(|e| RunnerError::io(output, e))
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [input, output] = args.as_slice() else {
        eprintln!("usage: stream_seeds IN OUT");
        return ExitCode::from(2);
    };
    match convert(Path::new(input), Path::new(output)) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("stream_seeds: {e}");
            ExitCode::FAILURE
        }
    }
}
