//! Seed 000's Tables 3, 4, 5 and 7: every published A* number on the twelve paper maps.
//!
//! The maps in `maps/paper/` were reconstructed so that the paper's rules reproduce its
//! tables; `maps/paper/published.toml` holds the numbers. With A*'s defaults (4-connected,
//! right-left-down-up, Manhattan, FIFO) each of the 12 x 9 = 108 A* numbers must come out.

use std::path::PathBuf;

use planner_api::{Budget, Cell, Connectivity, MoveSet, PathRule, Planner, Problem, Status};
use planner_astar::{AStar, Config};

#[test]
fn astar_reproduces_every_published_number() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../maps/paper");
    let published: toml::Table =
        toml::from_str(&std::fs::read_to_string(root.join("published.toml")).unwrap()).unwrap();
    let four = MoveSet::standard(Connectivity::Four);
    let mut astar = AStar::new(Config::default()).unwrap();
    let mut checked = 0;
    for (map, entry) in &published {
        let file = entry["file"].as_str().unwrap();
        let grid = planner_maps::read_map(&root.join(file)).unwrap().grid;
        let n = grid.width() - 1;
        let problem = Problem::new(&grid, Cell::new(0, 0), Cell::new(n, n)).unwrap();
        let outcome = astar.plan(&problem, &Budget::unlimited());
        assert_eq!(outcome.status, Status::Found, "{map}");
        let path = outcome.path.as_ref().unwrap();
        path.validate(&grid, PathRule::Moves(&four)).unwrap();
        let m = path.metrics();
        for (name, value) in entry["astar"].as_table().unwrap() {
            let expected = value.as_integer().unwrap() as u64;
            let actual = match name.as_str() {
                "steps" => m.steps,
                "turns" => m.turns,
                "score" => m.score,
                counter => outcome.counters.get(counter).unwrap(),
            };
            assert_eq!(actual, expected, "{map} A* {name}");
            checked += 1;
        }
    }
    assert_eq!(checked, 108);
}
