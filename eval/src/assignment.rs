//! Linear assignment (the Hungarian method) in the three forms the scoring needs, on
//! `pathfinding`'s Kuhn–Munkres solver. Real-valued costs are quantised to integers relative
//! to the largest one (2^30 steps), so only pairs whose totals differ by less than about 1e-9
//! of the largest cost can be ordered differently from an exact float solver.

use pathfinding::{kuhn_munkres::kuhn_munkres, matrix::Matrix};

/// Quantisation steps between the smallest and the largest real-valued cost.
const STEPS: i64 = 1 << 30;

/// The pairs (row, column) of a matching with as many pairs as possible and, among those, the
/// least total cost; `None` marks pairs that may not match. This is what py-motmetrics'
/// `linear_sum_assignment` returns for a cost matrix with NaN for forbidden pairs.
pub fn min_cost_matching(costs: &[Vec<Option<f64>>]) -> Vec<(usize, usize)> {
    let valid = costs.iter().flatten().flatten().copied();
    let lowest = valid.clone().fold(f64::INFINITY, f64::min);
    let highest = valid.fold(f64::NEG_INFINITY, f64::max);
    if lowest > highest {
        return Vec::new();
    }
    let n = costs.len().min(costs[0].len()) as i64;
    let steps = steps_for(n);
    // Every allowed pair outweighs any sum of cost differences, so the number of pairs comes
    // first and the total cost second.
    let pair = (n + 1) * steps + 1;
    let weights: Vec<Vec<i64>> = costs
        .iter()
        .map(|row| {
            row.iter()
                .map(|cost| {
                    cost.map_or(0, |c| pair - quantise(c - lowest, highest - lowest, steps))
                })
                .collect()
        })
        .collect();
    solve(&weights)
        .into_iter()
        .filter(|&(r, c)| costs[r][c].is_some())
        .collect()
}

/// The pairs of an assignment of min(rows, columns) pairs with the largest total weight
/// (weights ≥ 0): scipy's `linear_sum_assignment(-weights)`, as TrackEval's HOTA calls it.
pub fn max_weight_assignment(weights: &[Vec<f64>]) -> Vec<(usize, usize)> {
    let highest = weights.iter().flatten().copied().fold(0.0, f64::max);
    let n = weights.len().min(weights.first().map_or(0, Vec::len)) as i64;
    let steps = steps_for(n);
    let quantised: Vec<Vec<i64>> = weights
        .iter()
        .map(|row| row.iter().map(|&w| quantise(w, highest, steps)).collect())
        .collect();
    solve(&quantised)
}

/// The largest total weight of a matching between rows and columns with integer weights ≥ 0,
/// and its pairs (pairs of weight 0 left out).
pub fn max_weight_matching(weights: &[Vec<u32>]) -> (u64, Vec<(usize, usize)>) {
    let signed: Vec<Vec<i64>> = weights
        .iter()
        .map(|row| row.iter().map(|&w| i64::from(w)).collect())
        .collect();
    let pairs: Vec<(usize, usize)> = solve(&signed)
        .into_iter()
        .filter(|&(r, c)| weights[r][c] > 0)
        .collect();
    (
        pairs.iter().map(|&(r, c)| u64::from(weights[r][c])).sum(),
        pairs,
    )
}

/// Steps such that n pairs of weight up to (n + 1) · steps cannot overflow.
fn steps_for(n: i64) -> i64 {
    STEPS.min(i64::MAX / 8 / (n + 1).pow(2)).max(1)
}

/// `value` in [0, range] as an integer in [0, steps].
fn quantise(value: f64, range: f64, steps: i64) -> i64 {
    if range > 0.0 {
        (value / range * steps as f64).round() as i64
    } else {
        0
    }
}

/// A complete assignment of the smaller side with the largest total weight.
fn solve(weights: &[Vec<i64>]) -> Vec<(usize, usize)> {
    let rows = weights.len();
    let columns = weights.first().map_or(0, Vec::len);
    if rows == 0 || columns == 0 {
        return Vec::new();
    }
    let transposed = rows > columns;
    let matrix = if transposed {
        Matrix::from_fn(columns, rows, |(c, r)| weights[r][c])
    } else {
        Matrix::from_fn(rows, columns, |(r, c)| weights[r][c])
    };
    let (_, assigned) = kuhn_munkres(&matrix);
    assigned
        .into_iter()
        .enumerate()
        .map(|(a, b)| if transposed { (b, a) } else { (a, b) })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fewest_misses_first_then_least_cost() {
        // Greedy would pair (0, 0) at 0.1 and leave row 1 alone; two pairs beat one.
        let costs = vec![vec![Some(0.1), Some(0.5)], vec![Some(0.2), None]];
        let mut pairs = min_cost_matching(&costs);
        pairs.sort();
        assert_eq!(pairs, [(0, 1), (1, 0)]);
        // Among complete matchings the cheaper one.
        let costs = vec![
            vec![Some(1.0), Some(0.2), None],
            vec![Some(0.3), Some(0.4), Some(1.9)],
        ];
        let mut pairs = min_cost_matching(&costs);
        pairs.sort();
        assert_eq!(pairs, [(0, 1), (1, 0)]);
    }

    #[test]
    fn forbidden_pairs_never_match() {
        let costs = vec![vec![None, None], vec![None, Some(1.0)], vec![None, None]];
        assert_eq!(min_cost_matching(&costs), [(1, 1)]);
        assert!(min_cost_matching(&[vec![None; 3]]).is_empty());
        assert!(min_cost_matching(&[vec![]]).is_empty());
    }

    #[test]
    fn max_weight_assignment_covers_the_smaller_side() {
        let weights = vec![vec![0.9, 0.8], vec![0.85, 0.1], vec![0.0, 0.0]];
        let mut pairs = max_weight_assignment(&weights);
        pairs.sort();
        assert_eq!(pairs, [(0, 1), (1, 0)]);
    }

    #[test]
    fn max_weight_matching_is_exact_on_integers() {
        let weights = vec![vec![3, 2, 0], vec![3, 0, 0], vec![0, 0, 0]];
        let (total, mut pairs) = max_weight_matching(&weights);
        pairs.sort();
        assert_eq!(total, 5);
        assert_eq!(pairs, [(0, 1), (1, 0)]);
    }
}
