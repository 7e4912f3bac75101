//! Cell weights: a cost per cell on top of the free/blocked grid, and the exact move cost.
//!
//! A weighted [`Grid`](crate::Grid) carries one integer weight per cell, from 1 (neutral:
//! a move costs its length, as on an unweighted grid) to 65,535; blocked cells stay
//! blocked whatever their weight. A grid without weights behaves exactly as before, and
//! every planner that honours weights declares it
//! ([`PlannerSpecs::cell_costs`](crate::PlannerSpecs::cell_costs)).
//!
//! # The move cost ([`CostRule`])
//! A move of length `d` (1 for an axis move, `sqrt 2` for a diagonal, `sqrt(dx^2 + dy^2)` for
//! the longer moves) from a cell of weight `a` to a cell of weight `b` costs
//! - [`CostRule::Mean`] (the default): `d * (a + b) / 2`, the length times the mean of the
//!   two cells' weights: half the move in each cell. Issue 32 names it as the rule of
//!   warthog's weighted grids (Harabor's planning library, the code behind Carlson,
//!   Moghadam, Harabor, Stuckey and Ebrahimi's weighted JPS, JPSW, "Optimal Pathfinding on
//!   Weighted Grid Maps", AAAI 2023); that attribution was not checked against warthog's
//!   source here. It is symmetric: a path and its reverse cost
//!   the same.
//! - [`CostRule::Entered`]: `d * b`, the length times the weight of the cell entered,
//!   the way ROS 2 navigation's grid planners charge a move (Smac 2D adds the entered
//!   cell's normalized cost to the move's travel cost; NavFn propagates its potential
//!   through the cost of the cell reached). Not symmetric.
//!
//! Diagonal moves charge only their two end cells (the corner cells they pass are free or
//! the move is not allowed at all, by the move set's corner rule). A longer move (16, 32
//! or 48 directions) is charged the same way, for its two end cells only, though it
//! crosses others: a path of such moves is not least-cost by the cells it crosses, so
//! planners declare cell costs with 4 and 8 directions only (A*'s specs name `moves` in
//! [`PlannerSpecs::cell_costs_only_with`](crate::PlannerSpecs::cell_costs_only_with)).
//!
//! # Exact integer arithmetic
//! Costs are [`Cost`]s (units of `2^-32`). Let `half` be the move's [`Cost::of_move`]
//! halved, rounded down to a whole unit; then the move costs `half * (a + b)` units (mean)
//! or `half * 2 b` units (entered): one integer product per move ([`CostRule::factors`]).
//! For 4 and 8 directions the move costs [`Cost::ONE`] and [`Cost::SQRT_2`] are even, so
//! `half` is exact and a weighted path's cost is exactly `(A * ONE + B * SQRT_2) / 2` for
//! integers `A, B`: twice an octile cost. Equal real costs are therefore equal integers,
//! and [`crate::cost`]'s proof applies to the doubled values: **every comparison of
//! weighted 4- and 8-connected costs up to `Cost::EXACT_LIMIT / 2` = 125,898 is exact**
//! (beyond it the error bound of [`crate::cost`] holds for the doubled value). For
//! 16, 32 and 48 directions an odd move cost loses half a unit when halved.
//!
//! # The range
//! Costs are [`Cost`]s, which saturate at [`Cost::MAX`] (about 4.29e9). A path of `n`
//! moves through weights of at most `w` costs at most about `1.42 n w`, so only weights
//! make a cost that large (a corridor of 66,000 cells of weight 65,535 costs 4.33e9). Where
//! a search's costs saturate, paths that costly compare equal: a planner that can still
//! trace a path returns it (A\*, weighted JPS, lexastar, bidirectional A\*, coverage's
//! returns), and the runner records that path's true cost ([`crate::Grid::path_cost_f64`])
//! and says in the run's `error` that it is not known to be least-cost; LPA\* and D\* Lite,
//! which trace their path by the costs, end with
//! [`Outcome::cost_overflow`](crate::Outcome::cost_overflow) set instead. Below the limit
//! nothing changes.
//!
//! # Heuristics
//! Every move costs at least its length times the smallest weight `w_min` of the grid
//! ([`Weights::min`]), so a distance estimate that never overestimates the length stays
//! admissible (and consistent, if it was) when multiplied by `w_min`. The multiplication is
//! an integer one ([`Cost::times`]), exact.
//!
//! ```
//! use planner_api::{Cell, Cost, CostRule, Grid};
//!
//! let grid = Grid::from_ascii("...\n...").unwrap();
//! let grid = grid.with_weights(vec![1, 3, 5, 2, 2, 2], CostRule::Mean).unwrap();
//! // Right from weight 1 to weight 3: 1 * (1 + 3) / 2 = 2.
//! assert_eq!(grid.move_cost(Cell::new(0, 0), Cell::new(1, 0)), Cost::steps(2));
//! // Diagonal from weight 3 to weight 2: sqrt 2 * 5 / 2, exactly.
//! assert_eq!(
//!     grid.move_cost(Cell::new(1, 0), Cell::new(2, 1)).units(),
//!     Cost::SQRT_2.units() / 2 * 5
//! );
//! // The entered cell's weight only: 5 for the move onto (2, 0).
//! let entered = grid.clone().with_rule(CostRule::Entered);
//! assert_eq!(entered.move_cost(Cell::new(1, 0), Cell::new(2, 0)), Cost::steps(5));
//! assert_eq!(grid.weights().unwrap().min(), 1);
//! ```

use serde::{Deserialize, Serialize};

use crate::cost::Cost;

/// How a move's cost follows from its length and the weights of its two cells (see the
/// [module docs](self)).
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize, PartialOrd, Ord,
)]
#[serde(rename_all = "snake_case")]
pub enum CostRule {
    /// Length times the mean of the two cells' weights (module docs).
    #[default]
    Mean,
    /// Length times the weight of the cell entered (module docs).
    Entered,
}

impl CostRule {
    /// `(k_from, k_to)`: a move costs `half * (k_from * a + k_to * b)` units, with `half` its
    /// length's [`Cost`] units halved (rounded down), `a` the weight of the cell left and
    /// `b` of the cell entered. `(1, 1)` for the mean, `(0, 2)` for the entered cell.
    pub const fn factors(self) -> (u64, u64) {
        match self {
            CostRule::Mean => (1, 1),
            CostRule::Entered => (0, 2),
        }
    }

    /// The rule's name in configs: `mean` or `entered`.
    pub const fn name(self) -> &'static str {
        match self {
            CostRule::Mean => "mean",
            CostRule::Entered => "entered",
        }
    }
}

/// The cost of a move whose unweighted cost is `length` from a cell of weight `from` to a
/// cell of weight `to` under `rule` (module docs), saturating at [`Cost::MAX`].
#[inline]
pub fn weighted_move_cost(length: Cost, from: u16, to: u16, rule: CostRule) -> Cost {
    let (k_from, k_to) = rule.factors();
    let factor = k_from * u64::from(from) + k_to * u64::from(to);
    Cost::from_units((length.units() / 2).saturating_mul(factor))
}

/// The weight layer of a grid: one weight per cell (row-major, as the grid), the rule, and
/// the extremes with the number of cells holding each (derived from the cells, so that
/// [`crate::Grid::set_weight`] rescans them only when the last cell holding an extreme
/// leaves it).
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Weights {
    cells: Vec<u16>,
    rule: CostRule,
    min: u16,
    max: u16,
    at_min: usize,
    at_max: usize,
}

impl Weights {
    /// The weights; precondition (checked by [`crate::Grid::with_weights`]): none is 0.
    pub(crate) fn new(cells: Vec<u16>, rule: CostRule) -> Weights {
        let mut weights = Weights {
            cells,
            rule,
            min: 1,
            max: 1,
            at_min: 0,
            at_max: 0,
        };
        weights.rescan();
        weights
    }

    /// Recomputes the extremes and their counts from the cells.
    fn rescan(&mut self) {
        self.min = self.cells.iter().copied().min().unwrap_or(1);
        self.max = self.cells.iter().copied().max().unwrap_or(1);
        self.at_min = self.cells.iter().filter(|&&w| w == self.min).count();
        self.at_max = self.cells.iter().filter(|&&w| w == self.max).count();
    }

    /// The weights, row-major (index with [`crate::Grid::index`]).
    pub fn cells(&self) -> &[u16] {
        &self.cells
    }

    /// The move cost rule.
    pub fn rule(&self) -> CostRule {
        self.rule
    }

    /// The smallest weight of any cell (blocked cells included, so it stays a lower bound
    /// when cells are freed): what heuristics are multiplied by.
    pub fn min(&self) -> u16 {
        self.min
    }

    /// The largest weight of any cell.
    pub fn max(&self) -> u16 {
        self.max
    }

    pub(crate) fn set_rule(&mut self, rule: CostRule) {
        self.rule = rule;
    }

    /// Sets cell `index`'s weight (precondition: in range, not 0), keeping the extremes
    /// exact: in constant time, unless the cell was the last holding an extreme and leaves
    /// it (then the cells are rescanned).
    pub(crate) fn set(&mut self, index: usize, weight: u16) {
        let Some(cell) = self.cells.get_mut(index) else {
            return;
        };
        let old = std::mem::replace(cell, weight);
        if old == weight {
            return;
        }
        if (old == self.min && self.at_min == 1) || (old == self.max && self.at_max == 1) {
            self.rescan();
            return;
        }
        // The old weight leaves an extreme held by other cells too; the new one may join
        // or pass one.
        self.at_min -= usize::from(old == self.min);
        self.at_max -= usize::from(old == self.max);
        match weight.cmp(&self.min) {
            std::cmp::Ordering::Less => (self.min, self.at_min) = (weight, 1),
            std::cmp::Ordering::Equal => self.at_min += 1,
            std::cmp::Ordering::Greater => {}
        }
        match weight.cmp(&self.max) {
            std::cmp::Ordering::Greater => (self.max, self.at_max) = (weight, 1),
            std::cmp::Ordering::Equal => self.at_max += 1,
            std::cmp::Ordering::Less => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Random weight changes (a few distinct values, so that extremes are often shared and
    /// often left) keep the extremes and their counts equal to a fresh scan's.
    #[test]
    fn set_keeps_the_extremes_of_a_fresh_scan() {
        let mut xorshift = crate::test_rng::xorshift(0x2545_f491_4f6c_dd1d);
        let mut next = |n: u64| xorshift() % n;
        for len in [1usize, 2, 5, 40] {
            let cells = (0..len).map(|_| 1 + next(4) as u16).collect();
            let mut weights = Weights::new(cells, CostRule::Mean);
            for _ in 0..2_000 {
                let index = next(len as u64) as usize;
                weights.set(index, 1 + next(5) as u16);
                assert_eq!(weights, Weights::new(weights.cells.clone(), CostRule::Mean));
            }
        }
    }
}
