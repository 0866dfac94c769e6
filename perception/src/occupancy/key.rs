//! Integer voxel coordinates: the voxel holding a point, the block holding a voxel, a voxel's
//! slot inside its block.

use super::block::BLOCK_SIDE;

/// `floor(v)` as an integer (saturating), without a call to the C library's `floor`: the
/// build's baseline x86-64 has no rounding instruction.
pub(super) fn floor_i32(v: f64) -> i32 {
    let truncated = v as i32;
    truncated.saturating_sub(i32::from(f64::from(truncated) > v))
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
    fn negative_voxels_belong_to_negative_blocks() {
        let side = BLOCK_SIDE as i32;
        assert_eq!(block_key([-1, 0, side]), [-1, 0, 1]);
        assert_eq!(local_index([-1, 0, 0]), BLOCK_SIDE - 1);
        assert_eq!(voxel_key(-0.01, 0.26, 0.0, 4.0), [-1, 1, 0]);
    }
}
