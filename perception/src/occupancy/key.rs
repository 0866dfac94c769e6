//! Integer voxel coordinates: the voxel holding a point, the block holding a voxel, a voxel's
//! slot inside its block.

use super::block::BLOCK_SIDE;

/// `floor(v)` as an integer (saturating), without a call to the C library's `floor`: the
/// build's baseline x86-64 has no rounding instruction.
pub(super) fn floor_i32(v: f64) -> i32 {
    let truncated = v as i32;
    truncated.saturating_sub(i32::from(f64::from(truncated) > v))
}

/// Whether `v` lies in `[cell, cell + 1)`, where `floor_i32(v)` is `cell`: a test cheaper than
/// the floor, for a value likely to be in a known cell. False for NaN.
pub(super) fn in_cell(v: f64, cell: i32) -> bool {
    let low = f64::from(cell);
    low <= v && v < low + 1.0
}

/// The voxel holding `(x, y, z)`, in units where a voxel's edge is 1 (`inverse_resolution`
/// voxels per metre).
pub(super) fn voxel_key(x: f64, y: f64, z: f64, inverse_resolution: f64) -> [i32; 3] {
    [
        floor_i32(x * inverse_resolution),
        floor_i32(y * inverse_resolution),
        floor_i32(z * inverse_resolution),
    ]
}

/// The block holding voxel `key`.
pub(super) fn block_key(key: [i32; 3]) -> [i32; 3] {
    let s = BLOCK_SIDE.trailing_zeros();
    [key[0] >> s, key[1] >> s, key[2] >> s]
}

/// The slot of voxel `key` in its block (x fastest).
pub(super) fn local_index(key: [i32; 3]) -> usize {
    let m = BLOCK_SIDE as i32 - 1;
    let s = BLOCK_SIDE;
    (key[0] & m) as usize + (key[1] & m) as usize * s + (key[2] & m) as usize * s * s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn floor_matches_the_library_floor() {
        for v in [
            0.0, -0.0, 0.5, -0.5, 1.0, -1.0, 2.999_999, -2.000_001, 1e9, -1e9, 3e9, -3e9,
        ] {
            assert_eq!(floor_i32(v), v.floor() as i32, "{v}");
        }
    }

    #[test]
    fn a_value_in_a_cell_has_that_cell_as_its_floor() {
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        for _ in 0..100_000 {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let v = (state >> 11) as f64 / (1u64 << 53) as f64 * 200.0 - 100.0;
            let cell = floor_i32(v);
            assert!(in_cell(v, cell), "{v}");
            assert!(!in_cell(v, cell + 1) && !in_cell(v, cell - 1), "{v}");
        }
        for (v, cell) in [
            (-0.0, 0),
            (-1e-300, -1),
            (3.0, 3),
            (f64::from(i32::MAX), i32::MAX),
        ] {
            assert!(in_cell(v, cell) && floor_i32(v) == cell, "{v}");
        }
        for (v, cell) in [(f64::NAN, 0), (2.999_999_999, 3), (4.0, 3), (3e9, i32::MAX)] {
            assert!(!in_cell(v, cell), "{v}");
        }
    }

    #[test]
    fn negative_voxels_belong_to_negative_blocks() {
        let side = BLOCK_SIDE as i32;
        assert_eq!(block_key([-1, 0, side]), [-1, 0, 1]);
        assert_eq!(local_index([-1, 0, 0]), BLOCK_SIDE - 1);
        assert_eq!(voxel_key(-0.01, 0.26, 0.0, 4.0), [-1, 1, 0]);
    }
}
