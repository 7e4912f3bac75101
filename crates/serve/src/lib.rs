//! `gridplan serve` and the search's pictures: a local web page that plans on real maps
//! with the real planners and plays each search back ([`server`]), Posthoc search traces
//! ([`trace`]) and GIF animations ([`anim`]) of one run.
//!
//! Everything planned here goes through planner-runner, as `gridplan plan` does
//! ([`query`]), so the page's counters are `plan --json`'s for the same query. The page
//! (HTML, JavaScript, CSS under `assets/`) is embedded in the binary: no CDN, no build
//! step, works offline.
#![deny(missing_docs)]
#![cfg_attr(not(test), warn(clippy::unwrap_used))]

pub mod anim;
pub mod query;
pub mod safe;
pub mod server;
pub mod trace;

pub use server::{ServeError, ServeOptions, Server};

use std::path::Path;

/// `gridplan serve`: binds, prints the address (`serving DIR at http://ADDR/`, with the
/// chosen port when 0 was asked for) and answers until the process ends.
pub fn serve(options: &ServeOptions) -> Result<(), String> {
    let server = Server::bind(options).map_err(|e| e.to_string())?;
    let addr = server
        .addr()
        .ok_or_else(|| "the server has no IP address".to_string())?;
    println!("serving {} at http://{addr}/", options.dir.display());
    use std::io::Write as _;
    let _ = std::io::stdout().flush();
    server.run();
    Ok(())
}

/// `plan --trace FILE` and `plan --gif FILE`: writes the run's Posthoc trace and GIF
/// animation where asked (the run must have recorded its expanded cells). Refuses, before
/// writing anything, two of `svg` (which the caller writes), `trace` and `gif` naming one
/// file.
pub fn write_pictures(
    result: &planner_runner::plan::PlanResult,
    svg: Option<&Path>,
    trace: Option<&Path>,
    gif: Option<&Path>,
) -> Result<(), String> {
    let outputs: Vec<&Path> = [svg, trace, gif].into_iter().flatten().collect();
    for (i, a) in outputs.iter().enumerate() {
        if outputs[i + 1..].iter().any(|b| b == a) {
            return Err(format!(
                "{}: given for two of --svg, --trace and --gif",
                a.display()
            ));
        }
    }
    let write = |file: &Path, bytes: &[u8]| {
        std::fs::write(file, bytes).map_err(|e| format!("cannot write {}: {e}", file.display()))
    };
    if let Some(file) = trace {
        let text = trace::plan_trace_json(result).map_err(|e| e.to_string())?;
        write(file, text.as_bytes())?;
    }
    if let Some(file) = gif {
        let bytes = anim::plan_gif(result).map_err(|e| format!("{}: {e}", file.display()))?;
        write(file, &bytes)?;
    }
    Ok(())
}
