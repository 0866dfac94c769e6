//! The ground truth agrees with the points: counts, boxes, ranges, labels.

use std::collections::HashMap;

use nalgebra::{Point3, Vector3};
use trackd_sim::{GT_RANGE, PointLabel, Scenario, SimConfig, Simulation, TerrainKind};

/// Checks frames of a simulation: every object's npoints equals the points labelled with
/// it, those points lie in its box, and every object is within range.
fn check(sim: &Simulation, vehicle: usize, frames: &[usize]) -> usize {
    let world = sim.world();
    let mut seen = 0;
    for &i in frames {
        let f = sim.frame(vehicle, i);
        assert_eq!(f.points.len(), f.labels.len());
        let mut counts: HashMap<u32, usize> = HashMap::new();
        for l in &f.labels {
            if let Some(id) = l.object_id() {
                *counts.entry(id).or_default() += 1;
            }
        }
        let by_id: HashMap<u32, _> = f.objects.iter().map(|o| (o.id, o)).collect();
        for (id, n) in &counts {
            // A point on an object beyond 80 m has no row; any nearer one does.
            match by_id.get(id) {
                Some(o) => assert_eq!(o.npoints, *n, "frame {i} object {id}"),
                None => {
                    let far = f
                        .points
                        .iter()
                        .zip(&f.labels)
                        .filter(|(_, l)| l.object_id() == Some(*id))
                        .all(|(p, _)| p.x.hypot(p.y) > 70.0);
                    assert!(far, "frame {i}: object {id} has points but no row");
                }
            }
        }
        for o in &f.objects {
            assert!(o.center.xy().norm() <= GT_RANGE);
            assert_eq!(o.npoints, counts.get(&o.id).copied().unwrap_or(0));
            seen += usize::from(o.npoints > 0);
        }
        let t = f.timestamp - trackd_sim::simulation::START_UNIX_TIME;
        for (p, l) in f.points.iter().zip(&f.labels) {
            let Some(id) = l.object_id() else { continue };
            let v = Vector3::new(p.x as f64, p.y as f64, p.z as f64);
            // Exactly inside the world box (up to the range noise)...
            let w = f.velodyne_pose.transform_point(&Point3::from(v)).coords;
            let actor = world.actors.iter().find(|a| a.id == id).unwrap();
            let pose = actor.pose_at(t, &world.terrain);
            assert!(
                actor.box_contains(&pose, &w, 0.1),
                "frame {i} object {id}: {w}"
            );
            // ...and inside the written box, which is upright in the Velodyne frame.
            if let Some(o) = by_id.get(&id) {
                assert!(o.contains(&v, 0.25), "frame {i} object {id}: {v}");
            }
        }
    }
    seen
}

#[test]
fn ground_truth_matches_points_in_every_scenario() {
    for scenario in Scenario::ALL {
        let sim = Simulation::new(&SimConfig::new(scenario, 40, 3)).unwrap();
        let seen = check(&sim, 0, &[0, 20, 39]);
        assert!(seen >= 3, "{scenario}: only {seen} objects with points");
    }
}

#[test]
fn ground_points_lie_on_the_ground() {
    for terrain in [
        TerrainKind::Flat,
        TerrainKind::Tilted,
        TerrainKind::Undulating,
    ] {
        let config = SimConfig::new(Scenario::Intersection, 10, 5).with_terrain(terrain);
        let sim = Simulation::new(&config).unwrap();
        let f = sim.frame(0, 5);
        let ground: Vec<Vector3<f64>> = f
            .points
            .iter()
            .zip(&f.labels)
            .filter(|(_, l)| l.is_ground())
            .map(|(p, _)| {
                let v = Point3::new(p.x as f64, p.y as f64, p.z as f64);
                f.velodyne_pose.transform_point(&v).coords
            })
            .collect();
        assert!(ground.len() > 40_000, "{terrain:?}: {}", ground.len());
        let terrain_model = &sim.world().terrain;
        let worst = ground
            .iter()
            .map(|p| (p.z - terrain_model.height(p.xy())).abs())
            .fold(0.0, f64::max);
        // Range noise (2 cm, < 5σ) along steep and grazing beams.
        assert!(worst < 0.12, "{terrain:?}: {worst}");
        let static_points = f
            .labels
            .iter()
            .filter(|l| **l == PointLabel::Static)
            .count();
        assert!(static_points > 1000, "{terrain:?}: {static_points}");
    }
}
