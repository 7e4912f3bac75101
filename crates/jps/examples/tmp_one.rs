use planner_api::{Budget, Planner, Problem};
use planner_jps::{Config, Jps, Variant};
use std::time::Instant;
fn main() {
    let a: Vec<String> = std::env::args().collect();
    let root = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../maps/movingai");
    let name = &a[1];
    let v = match a[2].as_str() {
        "jps" => Variant::Jps,
        "jps_prime" => Variant::JpsPrime,
        _ => Variant::JpsPlus,
    };
    let grid = planner_maps::read_map(&root.join(format!("{name}.map")))
        .unwrap()
        .grid;
    let sc = planner_maps::read_scenarios(&root.join(format!("{name}.map.scen"))).unwrap();
    let mut p = Jps::new(Config {
        variant: v,
        marks: false,
        ..Config::default()
    })
    .unwrap();
    p.precompute(&grid);
    let t = Instant::now();
    let (mut exp, mut ins, mut peak, mut rel) = (0, 0, 0, 0);
    for s in &sc {
        let problem = Problem::new(&grid, s.start, s.goal).unwrap();
        let o = p.plan(&problem, &Budget::unlimited());
        exp += o.counters.get("n_expanded").unwrap();
        ins += o.counters.get("n_open_insertions").unwrap();
        rel += o.counters.get("n_relaxations").unwrap();
        peak = peak.max(o.counters.get("peak_open").unwrap());
    }
    println!(
        "{name} {v:?} ms={:.1} exp={exp} ins={ins} rel={rel} peak={peak}",
        t.elapsed().as_secs_f64() * 1e3
    );
}
