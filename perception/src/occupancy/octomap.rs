//! OctoMap's binary tree format (`.bt`): a text header, then the octree in pre-order, two bytes
//! per inner node holding two bits per child (00 unknown, 01 occupied leaf, 10 free leaf,
//! 11 inner node), children in OctoMap's order (x bit 1, y bit 2, z bit 4), 16 levels, keys
//! offset by 2^15 as in `OcTreeKey`.

/// Levels of an OctoMap tree.
const DEPTH: u32 = 16;
/// OctoMap's key offset (`tree_max_val`).
const KEY_OFFSET: i64 = 1 << (DEPTH - 1);

/// A node after maximum-likelihood pruning.
enum Node {
    Leaf { occupied: bool },
    Inner(Box<[Option<Node>; 8]>),
}

/// The `.bt` file of the given leaf voxels (voxel indices: floor(coordinate / resolution)).
/// Voxels outside OctoMap's key range (±2^15 voxels) are left out.
pub(super) fn write_bt(resolution: f64, leaves: &[([i32; 3], bool)]) -> Vec<u8> {
    let mut coded: Vec<(u64, bool)> = leaves
        .iter()
        .filter_map(|(k, occupied)| morton(k).map(|m| (m, *occupied)))
        .collect();
    coded.sort_unstable_by_key(|(m, _)| *m);
    coded.dedup_by_key(|(m, _)| *m);
    let root = (!coded.is_empty()).then(|| build(&coded, 0));
    let mut data = Vec::new();
    let size = match &root {
        Some(Node::Inner(children)) => {
            write_inner(children, &mut data);
            1 + count_children(children)
        }
        // A root collapsed to one leaf would need 2^48 voxels; there is nothing to write.
        Some(Node::Leaf { .. }) | None => 0,
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
fn morton(k: &[i32; 3]) -> Option<u64> {
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

/// The subtree of the (sorted, non-empty) voxels below a node at `level`, pruned: a node whose
/// eight children are leaves of one state becomes that leaf, as OctoMap's `prune()` does.
fn build(voxels: &[(u64, bool)], level: u32) -> Node {
    if level == DEPTH {
        return Node::Leaf {
            occupied: voxels[0].1,
        };
    }
    let mut children: [Option<Node>; 8] = Default::default();
    let mut start = 0;
    while start < voxels.len() {
        let child = child_at(voxels[start].0, level);
        let len = voxels[start..]
            .iter()
            .take_while(|(m, _)| child_at(*m, level) == child)
            .count();
        children[child] = Some(build(&voxels[start..start + len], level + 1));
        start += len;
    }
    let first = match &children[0] {
        Some(Node::Leaf { occupied }) => Some(*occupied),
        _ => None,
    };
    if let Some(state) = first
        && children
            .iter()
            .all(|c| matches!(c, Some(Node::Leaf { occupied }) if *occupied == state))
    {
        return Node::Leaf { occupied: state };
    }
    Node::Inner(Box::new(children))
}

fn write_inner(children: &[Option<Node>; 8], out: &mut Vec<u8>) {
    let mut bits = 0u16;
    for (i, child) in children.iter().enumerate() {
        let code = match child {
            None => 0b00,
            Some(Node::Leaf { occupied: true }) => 0b10, // bit 2i = 0, bit 2i+1 = 1
            Some(Node::Leaf { occupied: false }) => 0b01, // bit 2i = 1, bit 2i+1 = 0
            Some(Node::Inner(_)) => 0b11,
        };
        bits |= code << (2 * i);
    }
    out.extend_from_slice(&[(bits & 0xff) as u8, (bits >> 8) as u8]);
    for child in children.iter().flatten() {
        if let Node::Inner(grandchildren) = child {
            write_inner(grandchildren, out);
        }
    }
}

fn count_children(children: &[Option<Node>; 8]) -> usize {
    children
        .iter()
        .flatten()
        .map(|c| match c {
            Node::Leaf { .. } => 1,
            Node::Inner(g) => 1 + count_children(g),
        })
        .sum()
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
