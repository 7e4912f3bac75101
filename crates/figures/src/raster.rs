//! Large maps as pictures: the cell layers of a map of more than [`VECTOR_MAX_CELLS`] cells
//! (free, blocked, unknown, cost shading; expanded cells on top) as PNG images of at most
//! [`RASTER_MAX_SIDE`] pixels a side, embedded in the SVG as `data:` URIs.
//!
//! A pixel is a square block of `k` x `k` cells, `k` the smallest whole number that keeps
//! the picture within the pixels the map takes on the page (and within
//! [`RASTER_MAX_SIDE`]), so the picture has about one pixel per pixel of the figure. A
//! block's colour is the mean of its cells' colours (each cell coloured as the vector
//! drawing colours it), so a block of 16 cells of which 4 are blocked is a light grey;
//! expanded cells are a second picture on top, in which a block is expanded when any of
//! its cells was. The work is one pass over the cells, and the memory a few bytes per
//! pixel, whatever the size of the map.
//!
//! [`VECTOR_MAX_CELLS`]: crate::VECTOR_MAX_CELLS
//! [`RASTER_MAX_SIDE`]: crate::RASTER_MAX_SIDE

use image::codecs::png::{CompressionType, FilterType, PngEncoder};
use image::{ExtendedColorType, ImageEncoder};
use planner_api::{Cell, Grid};

use crate::{MapView, RASTER_MAX_SIDE};

/// An RGB colour.
pub(crate) type Rgb = [u8; 3];

/// `#rrggbb` as RGB (black for anything else).
pub(crate) fn rgb(hex: &str) -> Rgb {
    let byte = |i: usize| {
        hex.get(i..i + 2)
            .and_then(|h| u8::from_str_radix(h, 16).ok())
            .unwrap_or(0)
    };
    match hex.len() {
        7 if hex.starts_with('#') => [byte(1), byte(3), byte(5)],
        _ => [0, 0, 0],
    }
}

/// `top` over `base` at opacity `alpha` (0 to 1), rounded.
pub(crate) fn blend(base: Rgb, top: Rgb, alpha: f64) -> Rgb {
    let mix = |b: u8, t: u8| {
        (f64::from(b) + (f64::from(t) - f64::from(b)) * alpha)
            .round()
            .clamp(0.0, 255.0) as u8
    };
    [
        mix(base[0], top[0]),
        mix(base[1], top[1]),
        mix(base[2], top[2]),
    ]
}

/// The colours of a map's cells: what the vector drawing paints on each cell.
pub(crate) struct Palette {
    pub free: Rgb,
    pub blocked: Rgb,
    pub unknown: Rgb,
    /// The cost fill and its opacity at the highest weight.
    pub cost: Rgb,
    pub cost_opacity: f64,
}

/// The pixels of one map at one block size, and which blocks hold a free cell.
pub(crate) struct Raster {
    /// Cells per pixel side.
    pub k: u32,
    /// Pixels across and down.
    pub width: u32,
    pub height: u32,
    /// The map as a `data:` URI of a PNG (`None` if encoding failed, which it does not for
    /// an image in memory of these sizes).
    pub uri: Option<String>,
    /// Per pixel, whether its block holds a free cell (an expanded region's outline is
    /// drawn only towards such blocks).
    free: Vec<bool>,
}

/// The block size for a map of `longer` cells on its longer side drawn `cell_px` pixels a
/// cell: one pixel per pixel of the figure, at most [`RASTER_MAX_SIDE`] a side.
pub(crate) fn block_size(longer: u32, cell_px: f64) -> u32 {
    let on_page = (f64::from(longer) * cell_px).ceil();
    let side = if on_page.is_finite() {
        on_page.clamp(1.0, f64::from(RASTER_MAX_SIDE)) as u32
    } else {
        RASTER_MAX_SIDE
    };
    longer.div_ceil(side.max(1)).max(1)
}

impl Raster {
    /// The map's cell layers at `k` cells a pixel, coloured by `palette`.
    pub(crate) fn new(map: &MapView<'_>, k: u32, palette: &Palette) -> Raster {
        let grid = map.grid;
        let (w, h) = (grid.width() as usize, grid.height() as usize);
        let k = k.max(1);
        let ku = k as usize;
        let (width, height) = (grid.width().div_ceil(k), grid.height().div_ceil(k));
        let (pw, ph) = (width as usize, height as usize);
        // The cost shading by weight: one colour per weight from the lowest to the highest,
        // over a free and over an unknown cell.
        let weights = grid.weights().map(|w| (w.cells(), w.min(), w.max()));
        let shades: Vec<(Rgb, Rgb)> = match weights {
            Some((_, low, high)) if high > low => (low..=high)
                .map(|weight| {
                    let a = palette.cost_opacity * f64::from(weight - low) / f64::from(high - low);
                    (
                        blend(palette.free, palette.cost, a),
                        blend(palette.unknown, palette.cost, a),
                    )
                })
                .collect(),
            _ => Vec::new(),
        };
        let free_cells = grid.free_cells();
        let mut pixels = vec![0u8; pw * ph * 3];
        let mut free = vec![false; pw * ph];
        // Sums of one row of blocks: red, green, blue and the number of cells.
        let mut sums = vec![[0u64; 4]; pw];
        for y in 0..h {
            for x in 0..w {
                let i = y * w + x;
                let unknown = map.is_unknown(i);
                let colour = if free_cells[i] {
                    match (&weights, shades.is_empty()) {
                        (Some((cells, low, _)), false) => {
                            let shade = shades[usize::from(cells[i] - low)];
                            if unknown {
                                shade.1
                            } else {
                                shade.0
                            }
                        }
                        _ if unknown => palette.unknown,
                        _ => palette.free,
                    }
                } else if unknown {
                    palette.unknown
                } else {
                    palette.blocked
                };
                let sum = &mut sums[x / ku];
                for c in 0..3 {
                    sum[c] += u64::from(colour[c]);
                }
                sum[3] += 1;
                free[(y / ku) * pw + x / ku] |= free_cells[i];
            }
            if (y + 1) % ku == 0 || y + 1 == h {
                let row = y / ku;
                for (bx, sum) in sums.iter_mut().enumerate() {
                    let n = sum[3].max(1);
                    for c in 0..3 {
                        pixels[(row * pw + bx) * 3 + c] = ((sum[c] + n / 2) / n) as u8;
                    }
                    *sum = [0; 4];
                }
            }
        }
        let uri = png_uri(&pixels, width, height, ExtendedColorType::Rgb8);
        Raster {
            k,
            width,
            height,
            uri,
            free,
        }
    }

    /// The pixel of `cell`, which must be inside the grid.
    fn pixel(&self, cell: Cell) -> usize {
        (cell.y / self.k) as usize * self.width as usize + (cell.x / self.k) as usize
    }

    /// `expanded` as a picture over this one, as a `data:` URI: the blocks holding an
    /// expanded cell in `colour` at `opacity` or, with `outline`, only those of them next
    /// to a block that holds a free cell and none expanded, opaque (the region's edge).
    pub(crate) fn expanded_uri(
        &self,
        grid: &Grid,
        expanded: &[Cell],
        colour: Rgb,
        opacity: f64,
        outline: bool,
    ) -> Option<String> {
        let (pw, ph) = (self.width as usize, self.height as usize);
        let mut marked = vec![false; pw * ph];
        for &cell in expanded {
            if grid.contains(cell) {
                marked[self.pixel(cell)] = true;
            }
        }
        let alpha = (opacity.clamp(0.0, 1.0) * 255.0).round() as u8;
        let mut rgba = vec![0u8; pw * ph * 4];
        for y in 0..ph {
            for x in 0..pw {
                let i = y * pw + x;
                if !marked[i] {
                    continue;
                }
                let shown = if outline {
                    let open = |j: usize| !marked[j] && self.free[j];
                    (x > 0 && open(i - 1))
                        || (x + 1 < pw && open(i + 1))
                        || (y > 0 && open(i - pw))
                        || (y + 1 < ph && open(i + pw))
                } else {
                    true
                };
                if shown {
                    rgba[i * 4..i * 4 + 3].copy_from_slice(&colour);
                    rgba[i * 4 + 3] = if outline { 255 } else { alpha };
                }
            }
        }
        png_uri(&rgba, self.width, self.height, ExtendedColorType::Rgba8)
    }
}

/// `pixels` as a PNG in a `data:` URI.
fn png_uri(pixels: &[u8], width: u32, height: u32, colour: ExtendedColorType) -> Option<String> {
    let mut png = Vec::new();
    PngEncoder::new_with_quality(&mut png, CompressionType::Default, FilterType::NoFilter)
        .write_image(pixels, width, height, colour)
        .ok()?;
    let mut uri = String::with_capacity(22 + png.len().div_ceil(3) * 4);
    uri.push_str("data:image/png;base64,");
    base64(&png, &mut uri);
    Some(uri)
}

/// `bytes` in base64 (RFC 4648, with padding), appended to `out`.
pub(crate) fn base64(bytes: &[u8], out: &mut String) {
    const DIGITS: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    for chunk in bytes.chunks(3) {
        let n = chunk
            .iter()
            .enumerate()
            .fold(0u32, |n, (i, &b)| n | u32::from(b) << (16 - 8 * i));
        for i in 0..4 {
            if i <= chunk.len() {
                out.push(char::from(DIGITS[(n >> (18 - 6 * i)) as usize & 63]));
            } else {
                out.push('=');
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_of_the_rfc_vectors() {
        // RFC 4648, section 10.
        for (plain, coded) in [
            ("", ""),
            ("f", "Zg=="),
            ("fo", "Zm8="),
            ("foo", "Zm9v"),
            ("foob", "Zm9vYg=="),
            ("fooba", "Zm9vYmE="),
            ("foobar", "Zm9vYmFy"),
        ] {
            let mut out = String::new();
            base64(plain.as_bytes(), &mut out);
            assert_eq!(out, coded, "{plain}");
        }
        let mut out = String::new();
        base64(&[0xfb, 0xff], &mut out);
        assert_eq!(out, "+/8=");
    }

    #[test]
    fn blocks_keep_the_picture_within_the_page() {
        // 4096 cells at 0.28 px: 1147 px on the page, over 1024: k = ceil(4096 / 1024) = 4.
        assert_eq!(block_size(4096, 0.28), 4);
        // 600 cells at 1.96 px: 1176 px, capped at 1024: k = ceil(600 / 1024) = 1.
        assert_eq!(block_size(600, 1.96), 1);
        // 3000 cells at 0.1 px: 300 px, k = 10.
        assert_eq!(block_size(3000, 0.1), 10);
        assert_eq!(block_size(1, f64::INFINITY), 1);
        assert_eq!(block_size(5000, 0.0), 5000);
    }

    #[test]
    fn colours_parse_and_blend() {
        assert_eq!(rgb("#0072B2"), [0x00, 0x72, 0xb2]);
        assert_eq!(rgb("red"), [0, 0, 0]);
        // 255 + (0 - 255) * 0.3 = 178.5 -> 179 (half away from zero).
        assert_eq!(blend([255; 3], [0; 3], 0.3), [179; 3]);
    }
}
