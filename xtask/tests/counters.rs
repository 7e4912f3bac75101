//! Every counter a planner reports is documented in configs/README.md's "Columns of
//! runs.csv": each planner of the registry runs on a small map with its default
//! parameters, its test variants and the variants that add counters.

use std::collections::BTreeMap;
use std::path::Path;

use planner_api::{Budget, Cell, CoverageProblem, Problem};
use planner_registry::{Built, PLANNERS};

/// A 12 x 8 Moving AI map with two walls, so searches expand, jump, turn and check lines.
const MAP: &str = "type octile\nheight 8\nwidth 12\nmap\n............\n....@.......\n....@...@...\n....@...@...\n........@...\n..@@@...@...\n............\n............\n";

/// Parameter tables, beyond each planner's defaults and its registry test variants,
/// that make a planner report more counters.
const EXTRA: &[(&str, &str)] = &[
    ("jps", "variant = \"jps_plus\""),
    ("jps", "variant = \"jps_prime\""),
    ("jps", "goal_bounding = true"),
    ("bidirectional_astar", "moves = 4"),
    ("backtracking", "prune = \"bound\""),
];

/// The budget of every run: far more expansions than any search of the map needs but
/// Backtracking's, whose exhaustive enumeration of the map's paths it cuts short (its
/// counters are reported all the same).
const EXPANSIONS: u64 = 200_000;

/// Every counter name any planner reports, with the planners (registry names) reporting it.
fn reported() -> BTreeMap<String, Vec<&'static str>> {
    let grid = planner_maps::MapFormat::MovingAi
        .parse(MAP, "small.map")
        .unwrap()
        .grid;
    let (start, goal) = (Cell::new(0, 0), Cell::new(11, 7));
    for (name, _) in EXTRA {
        assert!(
            PLANNERS.iter().any(|e| e.name == *name),
            "{name} is no registry name"
        );
    }
    let mut names: BTreeMap<String, Vec<&'static str>> = BTreeMap::new();
    for entry in PLANNERS {
        let mut factories = entry.variants().unwrap();
        for (name, params) in EXTRA.iter().filter(|(n, _)| *n == entry.name) {
            let table: toml::Table = params.parse().unwrap();
            factories.push((entry.factory)(&table).unwrap_or_else(|e| panic!("{name}: {e}")));
        }
        for factory in factories {
            let counters = match factory.build().unwrap() {
                Built::Path(mut planner) => {
                    let problem = Problem::new(&grid, start, goal).unwrap();
                    planner
                        .plan(&problem, &Budget::expansions(EXPANSIONS))
                        .counters
                }
                Built::Coverage(mut planner) => {
                    let problem = CoverageProblem::new(&grid, start).unwrap();
                    planner
                        .cover(&problem, &Budget::expansions(EXPANSIONS))
                        .counters
                }
            };
            for (name, _) in counters.iter() {
                let planners = names.entry(name.to_owned()).or_default();
                if !planners.contains(&entry.name) {
                    planners.push(entry.name);
                }
            }
        }
    }
    names
}

/// The counter names configs/README.md's section "Columns of runs.csv" documents: the
/// first code span of each row of its counters table.
fn documented() -> Vec<String> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../configs/README.md");
    let text = std::fs::read_to_string(&path).unwrap();
    let section = text
        .split("\n## ")
        .find(|s| s.starts_with("Columns of runs.csv"))
        .expect("configs/README.md has no section \"Columns of runs.csv\"");
    section
        .lines()
        .filter_map(|l| l.strip_prefix("| `"))
        .filter_map(|l| l.split('`').next())
        .map(str::to_owned)
        .collect()
}

/// Every counter any planner reports has a row in configs/README.md's "Columns of
/// runs.csv" (none had: the file said only "one column per counter").
#[test]
fn every_counter_is_documented_in_configs_readme() {
    let documented = documented();
    let reported = reported();
    let missing: Vec<String> = reported
        .iter()
        .filter(|(name, _)| !documented.contains(name))
        .map(|(name, planners)| format!("{name} ({})", planners.join(", ")))
        .collect();
    let all: Vec<String> = reported
        .iter()
        .map(|(name, planners)| format!("{name} ({})", planners.join(", ")))
        .collect();
    assert!(
        missing.is_empty(),
        "counters without a row in configs/README.md's \"Columns of runs.csv\": {}\n\nevery counter reported: {}",
        missing.join("; "),
        all.join("; ")
    );
}
