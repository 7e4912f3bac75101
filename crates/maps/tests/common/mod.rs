//! Helpers shared by the test files: PNG files written byte by byte (chunks, CRCs, zlib
//! streams of stored blocks), for what the image crate's encoder does not write (a `tRNS`
//! chunk, interlacing, a header over too little data); and a count of the heap bytes the
//! calling thread holds, for the tests that bound what a reader allocates.
#![allow(dead_code)]

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

/// CRC-32 (ISO-HDLC, PNG's), bit by bit.
pub fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = !0u32;
    for &byte in bytes {
        crc ^= u32::from(byte);
        for _ in 0..8 {
            crc = if crc & 1 == 1 {
                (crc >> 1) ^ 0xedb8_8320
            } else {
                crc >> 1
            };
        }
    }
    !crc
}

/// Appends a PNG chunk: length, kind, data, CRC.
pub fn chunk(out: &mut Vec<u8>, kind: &[u8; 4], data: &[u8]) {
    out.extend((data.len() as u32).to_be_bytes());
    let start = out.len();
    out.extend(kind);
    out.extend(data);
    let crc = crc32(&out[start..]);
    out.extend(crc.to_be_bytes());
}

/// A zlib stream of `data` in stored (uncompressed) deflate blocks, with its Adler-32.
pub fn zlib_stored(data: &[u8]) -> Vec<u8> {
    let mut out = vec![0x78, 0x01];
    let blocks: Vec<&[u8]> = data.chunks(0xffff).collect();
    for (i, block) in blocks.iter().enumerate() {
        out.push(u8::from(i + 1 == blocks.len()));
        let len = block.len() as u16;
        out.extend(len.to_le_bytes());
        out.extend((!len).to_le_bytes());
        out.extend(*block);
    }
    if blocks.is_empty() {
        out.extend([1, 0, 0, 0xff, 0xff]);
    }
    let (mut a, mut b) = (1u32, 0u32);
    for &byte in data {
        a = (a + u32::from(byte)) % 65521;
        b = (b + a) % 65521;
    }
    out.extend(((b << 16) | a).to_be_bytes());
    out
}

/// A PNG: the signature, an `IHDR` of `width` x `height` with `depth` bits a sample of
/// colour type `colour` (0 grey, 2 RGB, 3 palette, 4 grey and alpha, 6 RGBA) and the
/// `interlace` method, then `extra` chunks (`tRNS`, `PLTE`, ...), one `IDAT` holding
/// `idat` as it is, and `IEND`.
pub fn png_file(
    (width, height): (u32, u32),
    (depth, colour, interlace): (u8, u8, u8),
    extra: &[(&[u8; 4], &[u8])],
    idat: &[u8],
) -> Vec<u8> {
    let mut out = b"\x89PNG\r\n\x1a\n".to_vec();
    let mut ihdr = width.to_be_bytes().to_vec();
    ihdr.extend(height.to_be_bytes());
    ihdr.extend([depth, colour, 0, 0, interlace]);
    chunk(&mut out, b"IHDR", &ihdr);
    for (kind, data) in extra {
        chunk(&mut out, kind, data);
    }
    chunk(&mut out, b"IDAT", idat);
    chunk(&mut out, b"IEND", &[]);
    out
}

/// The scanlines of `rows` (each row's bytes) as a PNG stores them unfiltered: a filter
/// byte 0 before each.
pub fn unfiltered(rows: &[Vec<u8>]) -> Vec<u8> {
    rows.iter()
        .flat_map(|row| std::iter::once(0).chain(row.iter().copied()))
        .collect()
}

/// The global allocator of this test binary: the system's, counting the bytes each thread
/// holds and the most it held since [`reset_peak`] (the other tests' threads keep their
/// own counts).
pub struct Counting;

thread_local! {
    static HELD: Cell<isize> = const { Cell::new(0) };
    static PEAK: Cell<isize> = const { Cell::new(0) };
}

fn count(delta: isize) {
    let _ = HELD.try_with(|held| {
        let now = held.get() + delta;
        held.set(now);
        let _ = PEAK.try_with(|peak| peak.set(peak.get().max(now)));
    });
}

// SAFETY: every call is passed on to the system allocator unchanged; the counters are
// const-initialised thread-local cells that allocate nothing. A failed allocation counts
// nothing.
#[allow(unsafe_code)]
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let ptr = unsafe { System.alloc(layout) };
        if !ptr.is_null() {
            count(layout.size() as isize);
        }
        ptr
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        let ptr = unsafe { System.alloc_zeroed(layout) };
        if !ptr.is_null() {
            count(layout.size() as isize);
        }
        ptr
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) };
        count(-(layout.size() as isize));
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let new = unsafe { System.realloc(ptr, layout, new_size) };
        if !new.is_null() {
            count(new_size as isize - layout.size() as isize);
        }
        new
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// Starts a measurement on this thread: the peak is set to what it holds now, which is
/// returned.
pub fn reset_peak() -> isize {
    let held = HELD.with(Cell::get);
    PEAK.with(|peak| peak.set(held));
    held
}

/// The most bytes this thread held above `baseline` (from [`reset_peak`]) since then.
pub fn peak_since(baseline: isize) -> u64 {
    (PEAK.with(Cell::get) - baseline).max(0) as u64
}
