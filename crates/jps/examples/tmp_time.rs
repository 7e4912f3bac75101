use planner_api::{Budget, Planner, Problem};
use planner_jps::{Config, Jps, Variant};
use std::time::Instant;
fn main() {
    let root = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../maps/movingai");
    for name in ["den520d", "random512-10-0"] {
        let grid = planner_maps::read_map(&root.join(format!("{name}.map")))
            .unwrap()
            .grid;
        let sc = planner_maps::read_scenarios(&root.join(format!("{name}.map.scen"))).unwrap();
        for v in [Variant::Jps, Variant::JpsPrime, Variant::JpsPlus] {
            let mut p = Jps::new(Config {
                variant: v,
                marks: false,
                ..Config::default()
            })
            .unwrap();
            let t = Instant::now();
            let prep = p.precompute(&grid);
            let tp = t.elapsed();
            let mut best = f64::MAX;
            let mut exp = 0;
            let mut mism = 0;
            for _ in 0..3 {
                let t = Instant::now();
                exp = 0;
                mism = 0;
                for s in &sc {
                    let problem = Problem::new(&grid, s.start, s.goal).unwrap();
                    let o = p.plan(&problem, &Budget::unlimited());
                    exp += o.counters.get("n_expanded").unwrap();
                    let l = o.path.map(|p| p.metrics().length).unwrap_or(-1.0);
                    if (l - s.optimal_length).abs() > 1e-4 * s.optimal_length.max(1.0) {
                        mism += 1;
                    }
                }
                best = best.min(t.elapsed().as_secs_f64() * 1e3);
            }
            println!(
                "{name} {v:?} ms={best:.1} exp={exp} mism={mism} prep_ms={:.2} {:?}",
                tp.as_secs_f64() * 1e3,
                prep
            );
        }
    }
}
