//! The seeded generator of this crate's randomised tests: Marsaglia's xorshift64 (shifts
//! 13, 7, 17), the same sequence as planner-testkit's, which this crate cannot depend on.

/// The xorshift64 sequence from `seed` (nonzero): each call returns the next state.
pub(crate) fn xorshift(seed: u64) -> impl FnMut() -> u64 {
    let mut state = seed;
    move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    }
}
