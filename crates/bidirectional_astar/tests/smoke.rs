use planner_api::{Budget, Cell, Grid, Planner, Problem, Status};
use planner_bidirectional_astar::{Config, BidirectionalAstar};

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
    let outcome = BidirectionalAstar::new(Config::default()).unwrap().plan(&problem, &Budget::unlimited());
    assert_eq!(outcome.status, Status::Found);
    let path = outcome.path.unwrap();
    assert_eq!(path.start(), Some(Cell::new(0, 1)));
    assert_eq!(path.goal(), Some(Cell::new(3, 1)));
    assert_eq!(path.metrics().steps, 5);
}
