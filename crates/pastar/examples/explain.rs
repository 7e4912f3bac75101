//! Prints what PA-star did on one problem: the obstacles the line crosses (size, centre,
//! circle, handover cells), the local segments after merging, the path and the counters.
//!
//! ```text
//! cargo run -p planner-pastar --example explain -- maps/pastar/two-140x120.map 20,10 70,110 [key=value ...]
//! ```
//! Parameters are the planner's config keys, e.g. `radius=size` or `r_threshold=12`.

use planner_api::{Budget, Cell, Problem};
use planner_pastar::{Config, PaStar};

fn cell(text: &str) -> Result<Cell, String> {
    let (x, y) = text
        .split_once(',')
        .ok_or(format!("{text:?}: expected x,y"))?;
    let n = |s: &str| s.trim().parse::<u32>().map_err(|e| format!("{s:?}: {e}"));
    Ok(Cell::new(n(x)?, n(y)?))
}

fn main() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [map, start, goal, params @ ..] = args.as_slice() else {
        return Err("usage: explain MAP X,Y X,Y [key=value ...]".into());
    };
    let file = planner_maps::read_map(std::path::Path::new(map)).map_err(|e| e.to_string())?;
    let mut table = toml::Table::new();
    for param in params {
        let (key, value) = param
            .split_once('=')
            .ok_or(format!("{param:?}: expected key=value"))?;
        let value = value
            .parse::<toml::Value>()
            .or_else(|_| {
                toml::from_str::<toml::Table>(&format!("v = {value}")).map(|t| t["v"].clone())
            })
            .unwrap_or_else(|_| toml::Value::String(value.to_string()));
        table.insert(key.to_string(), value);
    }
    let config: Config = toml::Value::Table(table)
        .try_into()
        .map_err(|e| e.to_string())?;
    let mut pastar = PaStar::new(config).map_err(|e| e.to_string())?;
    let problem = Problem::new(&file.grid, cell(start)?, cell(goal)?).map_err(|e| e.to_string())?;
    let report = pastar.plan_detailed(&problem, &Budget::unlimited());
    for (i, o) in report.obstacles.iter().enumerate() {
        println!(
            "obstacle {i}: first {} cells {} size {:.3} centre ({:.2}, {:.2}) radius {:.2} circle {:?} crossing {:?} handover {} -> {}",
            o.first_cell,
            o.n_cells,
            o.size,
            o.centre.0,
            o.centre.1,
            o.radius,
            o.circle,
            o.crossing,
            report.line[o.handover.0],
            report.line[o.handover.1]
        );
    }
    for pair in report.obstacles.windows(2) {
        let gap = report.line[pair[0].handover.1].euclidean(report.line[pair[1].handover.0]);
        println!(
            "gap N{} -> M{}: {gap:.3}",
            pair[0].first_cell, pair[1].first_cell
        );
    }
    for s in &report.segments {
        let len = s.path.as_ref().map(|p| p.metrics().length);
        println!(
            "segment {} -> {} ({} obstacles) local length {len:?}",
            s.start, s.goal, s.n_obstacles
        );
    }
    let o = &report.outcome;
    println!(
        "status {} length {:?}",
        o.status.as_str(),
        o.path.as_ref().map(|p| p.metrics().length)
    );
    println!("{}", o.counters);
    Ok(())
}
