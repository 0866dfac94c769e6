//! OctoMap's binary tree format (`.bt`): a text header, then the octree in pre-order, two bytes
//! per inner node holding two bits per child (00 unknown, 01 occupied leaf, 10 free leaf,
//! 11 inner node), children in OctoMap's order (x bit 1, y bit 2, z bit 4), 16 levels, keys
//! offset by 2^15 as in `OcTreeKey`.

/// Levels of an OctoMap tree.
const DEPTH: u32 = 16;
/// OctoMap's key offset (`tree_max_val`).
const KEY_OFFSET: i64 = 1 << (DEPTH - 1);

/// What a subtree became after maximum-likelihood pruning.
#[derive(Clone, Copy, PartialEq)]
enum Coded {
    Leaf { occupied: bool },
    Inner,
}

/// The `.bt` file of the given leaf voxels (voxel indices: floor(coordinate / resolution)).
/// Voxels outside OctoMap's key range (±2^15 voxels) are left out. Given in [`morton`] order
/// (as [`super::OccupancyMap::to_bt`] gives them), the sort takes one pass.
pub(super) fn write_bt(resolution: f64, leaves: &[([i32; 3], bool)]) -> Vec<u8> {
    let mut coded: Vec<(u64, bool)> = leaves
        .iter()
        .filter_map(|(k, occupied)| morton(k).map(|m| (m, *occupied)))
        .collect();
    coded.sort_by_key(|(m, _)| *m);
    coded.dedup_by_key(|(m, _)| *m);
    let mut data = Vec::new();
    let mut nodes = 0;
    let size = match coded.is_empty() {
        true => 0,
        false => match encode(&coded, 0, &mut data, &mut nodes) {
            Coded::Inner => 1 + nodes,
            // A root collapsed to one leaf would need 2^48 voxels; there is nothing to write.
            Coded::Leaf { .. } => 0,
        },
    };
    let mut out = format!(
        "# Octomap OcTree binary file\n# (feel free to add / change comments, but leave the first line as it is!)\n#\nid OcTree\nsize {size}\nres {resolution}\ndata\n"
    )
    .into_bytes();
    out.extend_from_slice(&data);
    out
}

/// The Morton code of a voxel's OctoMap key: at each level, from the root down, the child
/// index (x | y << 1 | z << 2), so sorting by it orders voxels as a pre-order walk does.
pub(super) fn morton(k: &[i32; 3]) -> Option<u64> {
    let mut key = [0u64; 3];
    for a in 0..3 {
        let v = i64::from(k[a]) + KEY_OFFSET;
        if !(0..(1 << DEPTH)).contains(&v) {
            return None;
        }
        key[a] = v as u64;
    }
    let mut m = 0u64;
    for bit in 0..DEPTH {
        let child =
            ((key[0] >> bit) & 1) | (((key[1] >> bit) & 1) << 1) | (((key[2] >> bit) & 1) << 2);
        m |= child << (3 * bit);
    }
    Some(m)
}

/// The child index of a Morton code at `level` (0 = the root's children).
fn child_at(m: u64, level: u32) -> usize {
    ((m >> (3 * (DEPTH - 1 - level))) & 7) as usize
}

/// Writes the subtree of the (sorted, non-empty) voxels below a node at `level` to `out` in
/// pre-order (the node's two bytes, then its inner children's subtrees), pruned: a node whose
/// eight children are leaves of one state becomes that leaf, as OctoMap's `prune()` does, and
/// writes nothing. Adds the nodes below it to `nodes`.
fn encode(voxels: &[(u64, bool)], level: u32, out: &mut Vec<u8>, nodes: &mut usize) -> Coded {
    if level == DEPTH {
        return Coded::Leaf {
            occupied: voxels[0].1,
        };
    }
    let (at, nodes_before) = (out.len(), *nodes);
    out.extend_from_slice(&[0, 0]);
    let mut children: [Option<Coded>; 8] = [None; 8];
    let mut start = 0;
    while start < voxels.len() {
        let child = child_at(voxels[start].0, level);
        let len = voxels[start..]
            .iter()
            .take_while(|(m, _)| child_at(*m, level) == child)
            .count();
        children[child] = Some(encode(&voxels[start..start + len], level + 1, out, nodes));
        start += len;
    }
    if let Some(leaf @ Coded::Leaf { .. }) = children[0]
        && children.iter().all(|c| *c == Some(leaf))
    {
        out.truncate(at);
        *nodes = nodes_before;
        return leaf;
    }
    let mut bits = 0u16;
    for (i, child) in children.iter().enumerate() {
        let code = match child {
            None => 0b00,
            Some(Coded::Leaf { occupied: true }) => 0b10, // bit 2i = 0, bit 2i+1 = 1
            Some(Coded::Leaf { occupied: false }) => 0b01, // bit 2i = 1, bit 2i+1 = 0
            Some(Coded::Inner) => 0b11,
        };
        bits |= code << (2 * i);
    }
    out[at..at + 2].copy_from_slice(&bits.to_le_bytes());
    *nodes += children.iter().flatten().count();
    Coded::Inner
}

#[cfg(test)]
mod tests {
    //! The file is parsed back with the format's own rules (as OctoMap's `readBinaryNode`
    //! does) and must give back exactly the voxels written.

    use std::collections::BTreeMap;

    use super::*;

    /// Parses a `.bt` file: (header size, resolution, leaf voxel → occupied, nodes read).
    fn parse(bytes: &[u8]) -> (usize, f64, BTreeMap<[i32; 3], bool>, usize) {
        let mut pos = 0;
        let mut lines = Vec::new();
        loop {
            let end = pos
                + bytes[pos..]
                    .iter()
                    .position(|&b| b == b'\n')
                    .expect("header line");
            let line = std::str::from_utf8(&bytes[pos..end])
                .expect("utf8 header")
                .to_string();
            pos = end + 1;
            if line == "data" {
                break;
            }
            lines.push(line);
        }
        assert_eq!(lines[0], "# Octomap OcTree binary file");
        let field = |name: &str| {
            lines
                .iter()
                .find_map(|l| l.strip_prefix(&format!("{name} ")))
                .expect(name)
                .to_string()
        };
        assert_eq!(field("id"), "OcTree");
        let size: usize = field("size").parse().unwrap();
        let res: f64 = field("res").parse().unwrap();
        let mut leaves = BTreeMap::new();
        let mut nodes = 0;
        if size > 0 {
            nodes = 1;
            read_node(bytes, &mut pos, [0; 3], 0, &mut leaves, &mut nodes);
        }
        assert_eq!(pos, bytes.len(), "trailing bytes");
        (size, res, leaves, nodes)
    }

    fn read_node(
        bytes: &[u8],
        pos: &mut usize,
        origin: [i64; 3],
        level: u32,
        leaves: &mut BTreeMap<[i32; 3], bool>,
        nodes: &mut usize,
    ) {
        let bits = u16::from(bytes[*pos]) | (u16::from(bytes[*pos + 1]) << 8);
        *pos += 2;
        let half = 1i64 << (DEPTH - 1 - level);
        for i in 0..8 {
            let (b0, b1) = ((bits >> (2 * i)) & 1, (bits >> (2 * i + 1)) & 1);
            let o = [
                origin[0] + if i & 1 != 0 { half } else { 0 },
                origin[1] + if i & 2 != 0 { half } else { 0 },
                origin[2] + if i & 4 != 0 { half } else { 0 },
            ];
            match (b0, b1) {
                (0, 0) => continue,
                (1, 1) => {
                    *nodes += 1;
                    read_node(bytes, pos, o, level + 1, leaves, nodes);
                }
                (b0, _) => {
                    *nodes += 1;
                    // A pruned leaf covers half³ voxels.
                    for dz in 0..half {
                        for dy in 0..half {
                            for dx in 0..half {
                                let k = [o[0] + dx, o[1] + dy, o[2] + dz]
                                    .map(|v| (v - KEY_OFFSET) as i32);
                                leaves.insert(k, b0 == 0);
                            }
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn empty_map_has_size_zero_and_no_data() {
        let (size, res, leaves, _) = parse(&write_bt(0.25, &[]));
        assert_eq!((size, res), (0, 0.25));
        assert!(leaves.is_empty());
    }

    #[test]
    fn voxels_round_trip_with_their_states_and_node_count() {
        let written: Vec<([i32; 3], bool)> = vec![
            ([0, 0, 0], true),
            ([-1, 0, 0], false),
            ([5, -7, 3], true),
            ([-32768, 32767, 0], false),
            ([1200, -300, 12], true),
        ];
        let (size, res, leaves, nodes) = parse(&write_bt(0.2, &written));
        assert_eq!(res, 0.2);
        assert_eq!(size, nodes, "header size must equal the nodes in the data");
        let expected: BTreeMap<[i32; 3], bool> = written.into_iter().collect();
        assert_eq!(leaves, expected);
    }

    #[test]
    fn eight_equal_siblings_are_pruned_into_one_leaf() {
        let cube: Vec<([i32; 3], bool)> = (0..8)
            .map(|i| ([i & 1, (i >> 1) & 1, (i >> 2) & 1], true))
            .collect();
        let (size, _, leaves, nodes) = parse(&write_bt(0.1, &cube));
        assert_eq!(leaves.len(), 8);
        assert!(leaves.values().all(|&o| o));
        // root + 14 inner levels + the pruned leaf at level 15
        assert_eq!((size, nodes), (16, 16));
        let mut mixed = cube.clone();
        mixed[3].1 = false;
        let (size, _, leaves, _) = parse(&write_bt(0.1, &mixed));
        assert_eq!(size, 16 + 8, "a mixed octant keeps its eight leaves");
        assert_eq!(leaves.values().filter(|&&o| !o).count(), 1);
    }

    #[test]
    fn out_of_range_voxels_are_left_out() {
        let (_, _, leaves, _) = parse(&write_bt(0.1, &[([40_000, 0, 0], true), ([1, 1, 1], true)]));
        assert_eq!(leaves.keys().copied().collect::<Vec<_>>(), vec![[1, 1, 1]]);
    }
}
