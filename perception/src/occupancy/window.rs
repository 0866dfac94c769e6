//! A dense window of block look-ups around the sensor, for the rays of one scan: a ray enters
//! some twenty blocks, present or not, and the rays of a scan cross the same ones over and
//! over, so each block of the window is looked up in the map's hash index once per scan and
//! then found by plain indexing. Keys outside the window go to the index every time.

/// A cell not looked up yet this scan.
const UNRESOLVED: u32 = u32::MAX;
/// A cell whose block the map does not hold.
const ABSENT: u32 = u32::MAX - 1;

/// Block slots (or their absence) of a box of block keys, filled as they are asked for.
#[derive(Debug, Default)]
pub(super) struct BlockWindow {
    min: [i32; 3],
    dims: [u32; 3],
    cells: Vec<u32>,
}

impl BlockWindow {
    /// Forgets every look-up and covers the block keys from `min` to `max` (inclusive; empty
    /// when any `max` is below its `min`).
    pub fn reset(&mut self, min: [i32; 3], max: [i32; 3]) {
        self.min = min;
        self.dims = [0, 1, 2].map(|a| u32::try_from(max[a] - min[a] + 1).unwrap_or(0));
        let len = self.dims.iter().map(|&d| d as usize).product();
        self.cells.clear();
        self.cells.resize(len, UNRESOLVED);
    }

    /// The slot of block `key`, `None` when the map does not hold it; `lookup` asks the map,
    /// the first time a key of the window is asked for and every time for one outside it.
    /// Valid while no block is added to the map or removed from it.
    #[inline]
    pub fn get(&mut self, key: [i32; 3], lookup: impl FnOnce() -> Option<u32>) -> Option<u32> {
        let rel = [0, 1, 2].map(|a| key[a].wrapping_sub(self.min[a]) as u32);
        if (0..3).any(|a| rel[a] >= self.dims[a]) {
            return lookup();
        }
        let (w, h) = (self.dims[0] as usize, self.dims[1] as usize);
        let cell = &mut self.cells[rel[0] as usize + w * (rel[1] as usize + h * rel[2] as usize)];
        if *cell == UNRESOLVED {
            *cell = lookup().unwrap_or(ABSENT);
        }
        (*cell != ABSENT).then_some(*cell)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn looks_each_key_of_the_window_up_once_and_keys_outside_every_time() {
        let mut window = BlockWindow::default();
        window.reset([-2, -2, -1], [2, 2, 1]);
        let lookups = std::cell::Cell::new(0);
        let get = |window: &mut BlockWindow, key: [i32; 3]| {
            window.get(key, || {
                lookups.set(lookups.get() + 1);
                (key[0] >= 0).then(|| key[0] as u32 * 10)
            })
        };
        assert_eq!(get(&mut window, [1, 0, 0]), Some(10));
        assert_eq!(get(&mut window, [1, 0, 0]), Some(10));
        assert_eq!(get(&mut window, [-1, 2, 1]), None);
        assert_eq!(get(&mut window, [-1, 2, 1]), None);
        assert_eq!(get(&mut window, [3, 0, 0]), Some(30));
        assert_eq!(get(&mut window, [3, 0, 0]), Some(30));
        assert_eq!(get(&mut window, [0, 0, -2]), Some(0));
        assert_eq!(lookups.get(), 5);
        window.reset([0, 0, 0], [0, 0, 0]);
        assert_eq!(get(&mut window, [1, 0, 0]), Some(10));
        assert_eq!(lookups.get(), 6);
    }

    #[test]
    fn an_empty_window_sends_everything_to_the_map() {
        let mut window = BlockWindow::default();
        window.reset([0, 0, 0], [-1, 5, 5]);
        assert_eq!(window.get([0, 0, 0], || Some(7)), Some(7));
        assert_eq!(window.get([0, 0, 0], || Some(8)), Some(8));
    }
}
