//! Ground removal against the simulator's per-point labels, on the points the default filter
//! keeps, in every scenario (three frames each): precision ≥ 0.95 and recall ≥ 0.98 of the
//! ground class on flat, tilted and undulating roads, and objects lose at most 10 % of their
//! points (the lowest centimetres of wheels and feet).

use trackd_perception::{Point, filter::FilterConfig, ground::GroundRemoval};
use trackd_sim::{PointLabel, Scenario, SimConfig, Simulation, TerrainKind};

/// Counts of one scan's classification.
#[derive(Debug, Default, Clone, Copy)]
struct Counts {
    true_ground: usize,
    false_ground: usize,
    missed_ground: usize,
    object_points: usize,
    object_removed: usize,
}

impl Counts {
    fn precision(&self) -> f64 {
        self.true_ground as f64 / (self.true_ground + self.false_ground).max(1) as f64
    }

    fn recall(&self) -> f64 {
        self.true_ground as f64 / (self.true_ground + self.missed_ground).max(1) as f64
    }

    fn object_loss(&self) -> f64 {
        self.object_removed as f64 / self.object_points.max(1) as f64
    }
}

/// Classifies the kept points of frame `index` of vehicle 0.
fn classify(sim: &Simulation, index: usize, removal: &mut GroundRemoval) -> Counts {
    let frame = sim.frame(0, index);
    let filter = FilterConfig::default();
    let (points, labels): (Vec<Point>, Vec<PointLabel>) = frame
        .points
        .iter()
        .zip(&frame.labels)
        .filter(|(p, _)| filter.keeps(p))
        .map(|(p, l)| (*p, *l))
        .unzip();
    let mut ground = Vec::new();
    removal.segment(&points, &mut ground);
    let mut counts = Counts::default();
    for (label, &is_ground) in labels.iter().zip(&ground) {
        match (label.is_ground(), is_ground) {
            (true, true) => counts.true_ground += 1,
            (false, true) => counts.false_ground += 1,
            (true, false) => counts.missed_ground += 1,
            (false, false) => {}
        }
        if label.object_id().is_some() {
            counts.object_points += 1;
            counts.object_removed += usize::from(is_ground);
        }
    }
    counts
}

fn check(terrain: TerrainKind) {
    let mut removal = GroundRemoval::default();
    for scenario in Scenario::ALL {
        let sim = Simulation::new(&SimConfig::new(scenario, 30, 11).with_terrain(terrain))
            .expect("simulation");
        for index in [0, 15, 29] {
            let c = classify(&sim, index, &mut removal);
            eprintln!(
                "{terrain:?} {:<12} frame {index:2}: ground precision {:.4} recall {:.4}, \
                 object points removed {:.3} ({} of {})",
                scenario.name(),
                c.precision(),
                c.recall(),
                c.object_loss(),
                c.object_removed,
                c.object_points
            );
            assert!(c.true_ground > 10_000, "{scenario:?} frame {index}: {c:?}");
            assert!(c.precision() >= 0.95, "{scenario:?} frame {index}: {c:?}");
            assert!(c.recall() >= 0.98, "{scenario:?} frame {index}: {c:?}");
            assert!(c.object_loss() <= 0.10, "{scenario:?} frame {index}: {c:?}");
        }
    }
}

#[test]
fn flat_roads() {
    check(TerrainKind::Flat);
}

#[test]
fn tilted_roads() {
    check(TerrainKind::Tilted);
}

#[test]
fn undulating_roads() {
    check(TerrainKind::Undulating);
}
