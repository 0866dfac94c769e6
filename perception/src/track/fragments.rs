//! Re-joining an object DBSCAN cut in two horizontally: a distant car whose middle rings
//! return nothing (dark paint, glass) falls apart into a low part and a high part, each too
//! low or floating to be an object. Clusters stacked one above the other, one's footprint
//! inside the other's, with a small vertical gap, are one object. So are a car's body and the
//! cabin set back on it (glass returns little, and the cabin's face is a metre behind the
//! body's): a high part no wider than the low one, within a cabin's setback of it. Riders side
//! by side are not stacked (their heights overlap) and stay apart.

use crate::Point;

/// Margin (m) around a footprint within which a stacked footprint counts as inside.
const FOOTPRINT_MARGIN: f32 = 0.3;
/// Share of the smaller footprint that must lie inside the larger one (grown by the margin).
const MIN_INSIDE: f32 = 0.7;
/// Largest vertical gap (m) between stacked parts; overlaps up to this much are allowed too.
const MAX_GAP: f32 = 1.0;
/// Smallest footprint side (m) assumed, so that a one-ring sliver has an area.
const MIN_SIDE: f32 = 0.1;
/// How far (m) a car's cabin face may sit behind (or ahead of) its body's face.
const CABIN_SETBACK: f32 = 1.5;
/// Largest vertical gap (m) between a body and its cabin.
const CABIN_MAX_GAP: f32 = 0.5;
/// How much taller (m) than the body's top a cabin may reach.
const CABIN_MAX_RISE: f32 = 1.2;
/// How much wider (m) than the body a cabin may look, on either axis.
const CABIN_MAX_EXTRA_SIDE: f32 = 0.3;

/// The axis-aligned bounds of one cluster.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounds {
    /// Lowest x, y, z.
    pub min: [f32; 3],
    /// Highest x, y, z.
    pub max: [f32; 3],
}

impl Bounds {
    /// The bounds of `points` (non-empty).
    pub fn of<'a>(points: impl IntoIterator<Item = &'a Point>) -> Self {
        let mut b = Self {
            min: [f32::MAX; 3],
            max: [f32::MIN; 3],
        };
        for p in points {
            for (k, v) in p.xyz().into_iter().enumerate() {
                b.min[k] = b.min[k].min(v);
                b.max[k] = b.max[k].max(v);
            }
        }
        b
    }

    /// The footprint's side along x or y, at least [`MIN_SIDE`].
    fn side(&self, k: usize) -> f32 {
        (self.max[k] - self.min[k]).max(MIN_SIDE)
    }

    /// Whether `self` and `other` are stacked parts of one object.
    fn stacked_with(&self, other: &Self) -> bool {
        let (low, high) = if self.min[2] <= other.min[2] {
            (self, other)
        } else {
            (other, self)
        };
        // Heights must not overlap much: parts side by side at the same height are two
        // objects DBSCAN kept apart on purpose.
        let gap = high.min[2] - low.max[2];
        if !(-0.1..=MAX_GAP).contains(&gap) {
            return false;
        }
        let (small, large) = if self.side(0) * self.side(1) <= other.side(0) * other.side(1) {
            (self, other)
        } else {
            (other, self)
        };
        small.inside_share(large, FOOTPRINT_MARGIN) >= MIN_INSIDE || high.is_cabin_of(low, gap)
    }

    /// Whether `self`, higher than `body` by `gap`, is the cabin of that car body: no wider,
    /// not much taller, within a cabin's setback.
    fn is_cabin_of(&self, body: &Self, gap: f32) -> bool {
        gap <= CABIN_MAX_GAP
            && self.max[2] <= body.max[2] + CABIN_MAX_RISE
            && (0..2).all(|k| self.side(k) <= body.side(k) + CABIN_MAX_EXTRA_SIDE)
            && self.inside_share(body, CABIN_SETBACK) >= MIN_INSIDE
    }

    /// The share of `self`'s footprint inside `other`'s grown by `margin` on every side.
    fn inside_share(&self, other: &Self, margin: f32) -> f32 {
        let mut inside = 1.0;
        for k in 0..2 {
            let lo = self.min[k].max(other.min[k] - margin);
            let hi = self.max[k].min(other.max[k] + margin);
            inside *= ((hi - lo).max(0.0) / self.side(k)).min(1.0);
        }
        inside
    }
}

/// Numbers the groups of stacked clusters: `groups[k]` is the group of cluster `k`, groups
/// numbered from 0 in order of their first cluster.
pub fn stacked_groups(bounds: &[Bounds], groups: &mut Vec<usize>) {
    groups.clear();
    groups.extend(0..bounds.len());
    for a in 0..bounds.len() {
        for b in a + 1..bounds.len() {
            if bounds[a].stacked_with(&bounds[b]) {
                let (ra, rb) = (root(groups, a), root(groups, b));
                if ra != rb {
                    groups[ra.max(rb)] = ra.min(rb);
                }
            }
        }
    }
    // Flatten to roots, then number the roots densely.
    for k in 0..groups.len() {
        groups[k] = root(groups, k);
    }
    let mut next = 0;
    let mut number = vec![usize::MAX; groups.len()];
    for g in groups.iter_mut() {
        if number[*g] == usize::MAX {
            number[*g] = next;
            next += 1;
        }
        *g = number[*g];
    }
}

/// Root of `k` in the union–find forest `parent`.
fn root(parent: &[usize], mut k: usize) -> usize {
    while parent[k] != k {
        k = parent[k];
    }
    k
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bounds(min: [f32; 3], max: [f32; 3]) -> Bounds {
        Bounds { min, max }
    }

    #[test]
    fn joins_the_halves_of_a_car_and_keeps_riders_apart() {
        let parts = [
            // A car at 48 m: its lower rings, then one upper ring.
            bounds([48.0, 0.0, 0.0], [48.5, 1.8, 0.6]),
            bounds([48.1, 0.1, 0.9], [48.2, 1.6, 1.2]),
            // Two riders side by side, 1 m apart.
            bounds([10.0, 0.0, 0.0], [11.8, 0.6, 1.8]),
            bounds([10.0, 1.0, 0.0], [11.8, 1.6, 1.8]),
            // A tree crown high above the first rider: too high above it.
            bounds([9.0, -1.0, 3.5], [13.0, 2.0, 6.0]),
        ];
        let mut groups = Vec::new();
        stacked_groups(&parts, &mut groups);
        assert_eq!(groups, vec![0, 0, 1, 2, 3]);
    }

    #[test]
    fn joins_a_car_body_and_its_set_back_cabin_but_not_a_crown_behind_a_hedge() {
        let parts = [
            // A car at 36 m seen from behind: the body's rear face, the cabin 1.2 m farther.
            bounds([35.1, -3.2, 0.37], [35.3, -1.4, 0.8]),
            bounds([36.3, -3.2, 0.97], [36.5, -1.6, 1.41]),
            // A hedge, and a tree crown 1 m behind it: wider than the hedge, far taller.
            bounds([20.0, 5.0, 0.0], [20.5, 7.0, 0.9]),
            bounds([21.0, 4.0, 1.2], [24.0, 8.0, 5.0]),
        ];
        let mut groups = Vec::new();
        stacked_groups(&parts, &mut groups);
        assert_eq!(groups, vec![0, 0, 1, 2]);
    }
}
