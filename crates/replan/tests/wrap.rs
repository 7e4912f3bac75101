//! A test double: an incremental planner that passes every call to another one but the
//! ones a test changes (the tests' watching, measuring, lost, blind and deaf planners).

use planner_api::{
    Budget, Cell, CellChange, ChangeError, Grid, IncrementalPlanner, Outcome, PlannerSpecs, Problem,
};

/// The calls a test changes; each default passes the call to the wrapped planner.
pub trait Change: Send + Sync {
    /// The name to give instead of the wrapped planner's.
    fn name(&self) -> Option<&str> {
        None
    }

    /// [`IncrementalPlanner::reset_within`] (and `reset`, with an unlimited budget).
    fn reset(
        &mut self,
        inner: &mut dyn IncrementalPlanner,
        problem: &Problem<'_>,
        budget: &Budget,
    ) {
        inner.reset_within(problem, budget)
    }

    /// [`IncrementalPlanner::apply`].
    fn apply(
        &mut self,
        inner: &mut dyn IncrementalPlanner,
        changes: &[CellChange],
    ) -> Result<(), ChangeError> {
        inner.apply(changes)
    }

    /// [`IncrementalPlanner::replan`].
    fn replan(&mut self, inner: &mut dyn IncrementalPlanner, budget: &Budget) -> Outcome {
        inner.replan(budget)
    }
}

/// `inner`, its calls changed by `change`.
pub struct Wrapped<C: Change> {
    pub inner: Box<dyn IncrementalPlanner>,
    pub change: C,
}

impl<C: Change> IncrementalPlanner for Wrapped<C> {
    fn name(&self) -> &str {
        self.change.name().unwrap_or_else(|| self.inner.name())
    }
    fn specs(&self) -> PlannerSpecs {
        self.inner.specs()
    }
    fn reset(&mut self, problem: &Problem<'_>) {
        self.change
            .reset(&mut *self.inner, problem, &Budget::unlimited())
    }
    fn reset_within(&mut self, problem: &Problem<'_>, budget: &Budget) {
        self.change.reset(&mut *self.inner, problem, budget)
    }
    fn grid(&self) -> Option<&Grid> {
        self.inner.grid()
    }
    fn start(&self) -> Option<Cell> {
        self.inner.start()
    }
    fn move_start(&mut self, cell: Cell) -> Result<(), ChangeError> {
        self.inner.move_start(cell)
    }
    fn apply(&mut self, changes: &[CellChange]) -> Result<(), ChangeError> {
        self.change.apply(&mut *self.inner, changes)
    }
    fn replan(&mut self, budget: &Budget) -> Outcome {
        self.change.replan(&mut *self.inner, budget)
    }
}
