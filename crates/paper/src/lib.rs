//! The seeds' table layouts in summary.md, as report sections a config chooses.
//!
//! - [`seed000`]: seed 000's Tables 3-8 (D, T, Score, time, memory per map and planner),
//!   with the published values compared.
//! - [`seed002`]: seed 002's Tables 6-14 (a proposed planner against its references,
//!   `R_length`, `R_time`, the timing tests) and CAPSO's lengths and convergence curve.
//! - [`seed003`]: seed 003's Tables I-II (times per map and planner).
//! - [`seed004`]: seed 004's coverage table.
//!
//! A paper layout shows only when a config names it in `sections = [...]` (or, for
//! [`seed000`], when a config without `sections` gives `published` values), and the
//! planners it singles out are named there as data (`{ name = "seed002", proposed =
//! "pastar" }`), never by a constant here: this crate depends on no planner crate and on
//! no planner list. [`catalogue`] places the layouts among planner-report's generic
//! sections; [`renderer`] is the report every front end (the CLI, the Python package,
//! xtask) hands to a sweep.
#![deny(missing_docs)]
#![cfg_attr(not(test), warn(clippy::unwrap_used))]

pub mod seed000;
pub mod seed002;
pub mod seed003;
pub mod seed004;

use planner_report::{generic_section, Renderer, Section};

/// Every section, generic and paper, in the order summary.md places them.
pub fn catalogue() -> Vec<Box<dyn Section>> {
    let mut all: Vec<Box<dyn Section>> =
        vec![Box::new(seed004::Coverage), Box::new(seed000::Seed000)];
    all.extend(generic_section("optimum"));
    all.push(Box::new(seed003::Seed003));
    all.extend(generic_section("repeats"));
    all.push(Box::new(seed002::Seed002));
    all.push(Box::new(seed002::Seed002Capso));
    all.extend(generic_section("aggregate"));
    all.extend(generic_section("paired"));
    all.extend(generic_section("charts"));
    all
}

/// The report with every section of [`catalogue`].
pub fn renderer() -> Renderer {
    Renderer::new(catalogue())
}
