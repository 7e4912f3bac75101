//! The scaffold's smoke test, kept: a path around a wall.

use planner_api::{Budget, Cell, Grid, Planner, Problem, Status};
use planner_jps::{Config, Jps};

#[test]
fn finds_a_path_around_a_wall() {
    let grid = Grid::from_ascii(
        "
        ....
        .##.
        ....
        ",
    )
    .unwrap();
    let problem = Problem::new(&grid, Cell::new(0, 1), Cell::new(3, 1)).unwrap();
    let outcome = Jps::new(Config::default())
        .unwrap()
        .plan(&problem, &Budget::unlimited());
    assert_eq!(outcome.status, Status::Found);
    let path = outcome.path.unwrap();
    assert_eq!(path.start(), Some(Cell::new(0, 1)));
    assert_eq!(path.goal(), Some(Cell::new(3, 1)));
    // Up, three right, down: no diagonal fits beside the wall without cutting a corner.
    assert_eq!(path.metrics().steps, 5);
    assert!((path.metrics().length - 5.0).abs() < 1e-9);
}
