//! Per-cell node arrays that need no clearing between searches.
//!
//! A search's node record carries a 32-bit stamp, `generation << 1 | closed`: a record
//! whose stamp is not this search's is unseen. Each search takes the next generation
//! ([`Stamped::begin`]), so the arrays are written only where the search goes; after
//! 2^31 - 1 searches the records are reset once and the count starts again.

/// This search's two stamp values.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Stamps {
    /// The generation (stamps shifted right by one).
    pub generation: u32,
    /// A node seen by this search and in OPEN: `generation << 1`.
    pub open: u32,
    /// A node expanded by this search: `generation << 1 | 1`.
    pub closed: u32,
}

/// A per-cell array of node records `T` (whose `Default` must carry stamp 0, unseen by
/// every search) and the generation of the last search.
///
/// ```
/// use planner_search::Stamped;
///
/// #[derive(Debug, Clone, Copy, Default)]
/// struct Node { g: f64, stamp: u32 }
///
/// let mut nodes = Stamped::<Node>::default();
/// nodes.fit(10);
/// let (stamps, records) = nodes.begin();
/// records[3] = Node { g: 1.5, stamp: stamps.closed };
/// // The next search sees cell 3 as unseen without any clearing.
/// let (next, records) = nodes.begin();
/// assert_ne!(records[3].stamp, next.open);
/// assert_ne!(records[3].stamp, next.closed);
/// ```
#[derive(Debug, Clone, Default)]
pub struct Stamped<T> {
    nodes: Vec<T>,
    generation: u32,
}

impl<T: Copy + Default> Stamped<T> {
    /// Sizes the array for `len` cells; a new size starts from fresh records.
    pub fn fit(&mut self, len: usize) {
        if self.nodes.len() != len {
            self.nodes = vec![T::default(); len];
            self.generation = 0;
        }
    }

    /// The number of records.
    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    /// Whether there are no records.
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// Starts a search: the next generation's stamps and the records.
    pub fn begin(&mut self) -> (Stamps, &mut [T]) {
        self.generation += 1;
        if self.generation >= 1 << 31 {
            self.nodes.fill(T::default());
            self.generation = 1;
        }
        let generation = self.generation;
        let stamps = Stamps {
            generation,
            open: generation << 1,
            closed: generation << 1 | 1,
        };
        (stamps, &mut self.nodes)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn generations_wrap_by_resetting_the_records() {
        let mut nodes = Stamped::<u32>::default();
        nodes.fit(4);
        let (stamps, records) = nodes.begin();
        assert_eq!((stamps.generation, stamps.open, stamps.closed), (1, 2, 3));
        records[0] = stamps.closed;
        nodes.generation = (1 << 31) - 1;
        let (stamps, records) = nodes.begin();
        assert_eq!(stamps.generation, 1);
        assert_eq!(records[0], 0, "records reset at the wrap");
        nodes.fit(4);
        assert_eq!(
            nodes.begin().0.generation,
            2,
            "same size keeps the generation"
        );
        nodes.fit(5);
        assert_eq!(nodes.begin().0.generation, 1);
        assert_eq!(nodes.len(), 5);
    }
}
