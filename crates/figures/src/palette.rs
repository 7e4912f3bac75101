//! Fixed colours: the Okabe-Ito palette for layers and the viridis ramp for time.

/// Layer colours, in the order layers receive them: the Okabe-Ito colour-blind-safe
/// palette (Okabe and Ito 2008, <https://jfly.uni-koeln.de/color/>), reordered so that the
/// first colours have the most contrast on white, with yellow last. Layer `i` gets
/// [`colour`]`(i)`: `PALETTE[i]` for the first eight, then distinct further colours.
pub const PALETTE: [&str; 8] = [
    "#0072B2", // blue
    "#D55E00", // vermillion
    "#009E73", // bluish green
    "#CC79A7", // reddish purple
    "#E69F00", // orange
    "#56B4E9", // sky blue
    "#000000", // black
    "#F0E442", // yellow
];

/// The colour of layer `i` within one figure: the eight [`PALETTE`] colours first, then
/// colours whose hues step by the golden angle (about 137.5 degrees) around the HSL
/// circle, alternating two lightness levels, so no two layers of one figure share a
/// colour (up to the 2^24 `#rrggbb` values).
pub fn colour(i: usize) -> String {
    if let Some(c) = PALETTE.get(i) {
        return (*c).to_string();
    }
    let k = (i - PALETTE.len()) as f64;
    let hue = (k * 137.507_764).rem_euclid(360.0);
    let lightness = if (i - PALETTE.len()) % 2 == 0 {
        0.42
    } else {
        0.58
    };
    let (r, g, b) = hsl_to_rgb(hue, 0.75, lightness);
    format!("#{r:02x}{g:02x}{b:02x}")
}

/// HSL (hue in degrees, saturation and lightness in [0, 1]) to 8-bit RGB.
fn hsl_to_rgb(hue: f64, saturation: f64, lightness: f64) -> (u8, u8, u8) {
    let chroma = (1.0 - (2.0 * lightness - 1.0).abs()) * saturation;
    let h = hue / 60.0;
    let x = chroma * (1.0 - (h.rem_euclid(2.0) - 1.0).abs());
    let (r, g, b) = match h as u32 {
        0 => (chroma, x, 0.0),
        1 => (x, chroma, 0.0),
        2 => (0.0, chroma, x),
        3 => (0.0, x, chroma),
        4 => (x, 0.0, chroma),
        _ => (chroma, 0.0, x),
    };
    let m = lightness - chroma / 2.0;
    let byte = |v: f64| ((v + m) * 255.0).round().clamp(0.0, 255.0) as u8;
    (byte(r), byte(g), byte(b))
}

/// Viridis (matplotlib's default map, perceptually uniform and colour-blind safe) at ten
/// evenly spaced points, 0 to 1.
const VIRIDIS: [(u8, u8, u8); 10] = [
    (0x44, 0x01, 0x54),
    (0x48, 0x28, 0x78),
    (0x3E, 0x4A, 0x89),
    (0x31, 0x68, 0x8E),
    (0x26, 0x82, 0x8E),
    (0x1F, 0x9E, 0x89),
    (0x35, 0xB7, 0x79),
    (0x6D, 0xCD, 0x59),
    (0xB4, 0xDE, 0x2C),
    (0xFD, 0xE7, 0x25),
];

/// The viridis colour at `t` in `[0, 1]` (clamped; NaN counts as 0), as `#rrggbb`,
/// interpolated linearly between the ten anchors.
pub(crate) fn ramp(t: f64) -> String {
    let t = if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) };
    let pos = t * (VIRIDIS.len() - 1) as f64;
    let i = (pos.floor() as usize).min(VIRIDIS.len() - 2);
    let f = pos - i as f64;
    let (a, b) = (VIRIDIS[i], VIRIDIS[i + 1]);
    let mix = |p: u8, q: u8| (f64::from(p) + (f64::from(q) - f64::from(p)) * f).round() as u8;
    format!(
        "#{:02x}{:02x}{:02x}",
        mix(a.0, b.0),
        mix(a.1, b.1),
        mix(a.2, b.2)
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layer_colours_do_not_repeat_within_a_figure() {
        let colours: Vec<String> = (0..64).map(colour).collect();
        let distinct: std::collections::BTreeSet<&String> = colours.iter().collect();
        assert_eq!(distinct.len(), colours.len());
        assert_eq!(colours[0], PALETTE[0]);
        assert_eq!(colours[7], PALETTE[7]);
        // Layer 8: hue 0, saturation 0.75, lightness 0.42: chroma 0.63, m 0.105, so
        // red (0.63 + 0.105) * 255 = 187.4 -> 187, green and blue 0.105 * 255 = 26.8 -> 27.
        assert_eq!(colours[8], "#bb1b1b");
    }

    #[test]
    fn ramp_ends_and_midpoint() {
        assert_eq!(ramp(0.0), "#440154");
        assert_eq!(ramp(1.0), "#fde725");
        assert_eq!(ramp(2.0), "#fde725");
        assert_eq!(ramp(f64::NAN), "#440154");
        // t = 1/9 is exactly the second anchor.
        assert_eq!(ramp(1.0 / 9.0), "#482878");
        // Halfway between anchors 4 (#26828e) and 5 (#1f9e89): (0x26+0x1f)/2 = 34.5 -> 35.
        assert_eq!(ramp(4.5 / 9.0), "#23908c");
    }
}
