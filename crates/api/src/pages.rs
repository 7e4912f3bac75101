//! [`Pages`]: a per-cell (or per-state) array whose memory is allocated in pages on first
//! write, so that a search touching few cells of a large grid holds little memory.
//!
//! A flat `Vec<T>` with one record per cell takes `cells x size_of::<T>()` bytes as soon
//! as it is sized, whatever the search then touches. `Pages` keeps one pointer per page of
//! [`PAGE_LEN`] records and allocates a page, filled with `T::default()`, the first time a
//! record in it is written; reads of a page never written give `T::default()`. The
//! records a planner keeps between searches stay valid (planners stamp them with a
//! generation rather than clearing them), and [`Pages::resident_bytes`] reports what is
//! held, which tests assert on.
//!
//! ```
//! use planner_api::pages::{Pages, PAGE_LEN};
//! let mut records: Pages<u32> = Pages::new(16_000_000);
//! assert_eq!(records.get(12_345_678), 0);
//! *records.get_mut(12_345_678) = 7;
//! *records.get_mut(12_345_679) = 8;
//! assert_eq!(records.get(12_345_678), 7);
//! assert_eq!(records.n_pages_allocated(), 1);
//! assert!(records.resident_bytes() < 16_000_000 / PAGE_LEN * 8 + PAGE_LEN * 4 + 64);
//! ```

/// Records per page: 1024 (a 24-byte record's page is 24 KiB).
pub const PAGE_LEN: usize = 1 << PAGE_BITS;
const PAGE_BITS: u32 = 10;

/// A lazily allocated array of `len` records of `T`; see the module docs.
#[derive(Debug, Clone, Default)]
pub struct Pages<T> {
    /// One thin pointer (8 bytes, `None` a null) per page.
    pages: Vec<Option<Box<[T; PAGE_LEN]>>>,
    len: usize,
    n_allocated: usize,
}

impl<T: Copy + Default> Pages<T> {
    /// `len` records, all `T::default()`, with no page allocated.
    pub fn new(len: usize) -> Pages<T> {
        Pages {
            pages: vec![None; len.div_ceil(PAGE_LEN)],
            len,
            n_allocated: 0,
        }
    }

    /// The number of records.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether there are no records.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Record `i` (`T::default()` when its page was never written). Panics when
    /// `i >= len`, as slice indexing does.
    #[inline]
    pub fn get(&self, i: usize) -> T {
        assert!(i < self.len, "record {i} of {}", self.len);
        match &self.pages[i >> PAGE_BITS] {
            Some(page) => page[i & (PAGE_LEN - 1)],
            None => T::default(),
        }
    }

    /// Record `i`, for writing: allocates its page (filled with `T::default()`) when it
    /// has none. Panics when `i >= len`.
    #[inline]
    pub fn get_mut(&mut self, i: usize) -> &mut T {
        assert!(i < self.len, "record {i} of {}", self.len);
        let page = &mut self.pages[i >> PAGE_BITS];
        if page.is_none() {
            self.n_allocated += 1;
        }
        let page = page.get_or_insert_with(|| Box::new([T::default(); PAGE_LEN]));
        &mut page[i & (PAGE_LEN - 1)]
    }

    /// Sets every allocated record back to `T::default()`, keeping the pages.
    pub fn fill_default(&mut self) {
        for page in self.pages.iter_mut().flatten() {
            page.fill(T::default());
        }
    }

    /// How many pages are allocated.
    pub fn n_pages_allocated(&self) -> usize {
        self.n_allocated
    }

    /// The bytes held: the allocated pages and the table of page pointers.
    pub fn resident_bytes(&self) -> usize {
        self.n_allocated * PAGE_LEN * std::mem::size_of::<T>()
            + self.pages.len() * std::mem::size_of::<Option<Box<[T; PAGE_LEN]>>>()
    }

    /// The bytes `len` records would hold with every page allocated.
    pub fn full_bytes(len: usize) -> u64 {
        let n_pages = len.div_ceil(PAGE_LEN) as u64;
        n_pages * (PAGE_LEN * std::mem::size_of::<T>()) as u64
            + n_pages * std::mem::size_of::<Option<Box<[T; PAGE_LEN]>>>() as u64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pages_are_allocated_on_first_write_only() {
        let mut pages: Pages<(u64, u8)> = Pages::new(3 * PAGE_LEN + 5);
        assert_eq!(pages.n_pages_allocated(), 0);
        assert_eq!(pages.get(3 * PAGE_LEN + 4), (0, 0));
        assert_eq!(pages.n_pages_allocated(), 0);
        pages.get_mut(3 * PAGE_LEN + 4).0 = 9;
        pages.get_mut(3 * PAGE_LEN).1 = 1;
        pages.get_mut(5).0 = 2;
        assert_eq!(pages.n_pages_allocated(), 2);
        assert_eq!(pages.get(3 * PAGE_LEN + 4), (9, 0));
        assert_eq!(pages.get(3 * PAGE_LEN), (0, 1));
        assert_eq!(pages.get(6), (0, 0));
        pages.fill_default();
        assert_eq!(pages.get(5), (0, 0));
        assert_eq!(pages.n_pages_allocated(), 2);
        let full = Pages::<(u64, u8)>::full_bytes(3 * PAGE_LEN + 5);
        assert_eq!(full, 4 * (PAGE_LEN as u64 * 16 + 8));
        assert_eq!(pages.resident_bytes(), 2 * PAGE_LEN * 16 + 4 * 8);
    }

    #[test]
    #[should_panic(expected = "record 10 of 10")]
    fn out_of_range_panics_like_a_slice() {
        Pages::<u8>::new(10).get(10);
    }
}
