//! OPEN's key ([`open_key`]) is `(f / EPSILON).round()`, computed without the library call.

use planner_theta_star::{open_key, EPSILON};

/// On halves of `EPSILON` and their neighbours, near 2^52 and 2^53 units, and on a million
/// pseudo-random lengths up to 2^20.
#[test]
fn open_key_is_the_rounded_quotient() {
    let mut units = vec![0.0, 0.5, 1.5, 2.5, 0.49999999999999994, 4503599627370495.5];
    for k in 0..64u32 {
        let half = f64::from(k) + 0.5;
        units.extend([half, half.next_down(), half.next_up()]);
    }
    for e in [52, 53, 56] {
        let p = 2f64.powi(e);
        units.extend([p, p.next_down(), p.next_up(), p - 0.5, p + 1.0]);
    }
    let mut state = 0x2545_f491_4f6c_dd1du64;
    for _ in 0..1_000_000 {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        units.push((state >> 11) as f64 / 2f64.powi(33) / EPSILON);
    }
    for x in units {
        let f = x * EPSILON;
        assert_eq!(open_key(f).units(), (f / EPSILON).round() as u64, "{f}");
    }
}
