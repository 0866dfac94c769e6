//! Objects of the ground truth: a class, a box size, a body and a trajectory.

use nalgebra::{Vector2, Vector3};

use crate::body::Body;
use crate::class::Class;
use crate::geometry::Primitive;
use crate::label::PointLabel;
use crate::material::Material;
use crate::terrain::Terrain;
use crate::trajectory::{PlanarState, Trajectory};

/// An object of the ground truth (parked or moving), global id across the fleet.
#[derive(Clone, Debug, PartialEq)]
pub struct Actor {
    /// Global object id (the same in every vehicle's ground truth).
    pub id: u32,
    /// KITTI class.
    pub class: Class,
    /// Box size: length, width, height (metres).
    pub size: [f64; 3],
    /// The solids it is made of.
    pub body: Body,
    /// Where it is over time.
    pub trajectory: Trajectory,
}

/// An actor's box at one time, in the world frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ActorPose {
    /// Box centre (metres).
    pub center: Vector3<f64>,
    /// Heading of the box's length axis (radians, counter-clockwise from east).
    pub yaw: f64,
    /// Velocity over ground (m/s).
    pub velocity: Vector2<f64>,
    /// Phase of the gait cycle (radians).
    pub gait: f64,
}

impl Actor {
    /// An actor of `class` and `size` with the body of its class.
    pub fn new(
        id: u32,
        class: Class,
        size: [f64; 3],
        paint: Material,
        trajectory: Trajectory,
    ) -> Self {
        Self {
            id,
            class,
            size,
            body: Body::of(class, size, paint),
            trajectory,
        }
    }

    /// The planar motion at time `t`.
    pub fn planar(&self, t: f64) -> PlanarState {
        self.trajectory.state(t)
    }

    /// The box at time `t`, standing upright on `terrain`.
    pub fn pose_at(&self, t: f64, terrain: &Terrain) -> ActorPose {
        let s = self.trajectory.state(t);
        let xy = s.pose.position;
        let gait = if self.body.stride > 0.0 {
            std::f64::consts::TAU * s.distance / self.body.stride
        } else {
            0.0
        };
        ActorPose {
            center: Vector3::new(xy.x, xy.y, terrain.height(xy) + self.size[2] / 2.0),
            yaw: s.pose.heading,
            velocity: s.velocity(),
            gait,
        }
    }

    /// Appends the actor's solids at `pose` to `out`.
    pub fn primitives(&self, pose: &ActorPose, out: &mut Vec<Primitive>) {
        let (sin, cos) = pose.yaw.sin_cos();
        let base = pose.center - Vector3::new(0.0, 0.0, self.size[2] / 2.0);
        out.extend(self.body.parts.iter().map(|part| {
            let o = part.offset_at(pose.gait);
            let center = base + Vector3::new(cos * o.x - sin * o.y, sin * o.x + cos * o.y, o.z);
            Primitive::new(
                part.shape,
                center,
                pose.yaw,
                part.material,
                PointLabel::Object(self.id),
            )
        }));
    }

    /// Whether a world point lies in the actor's box at `pose` (with `margin` metres added).
    pub fn box_contains(&self, pose: &ActorPose, p: &Vector3<f64>, margin: f64) -> bool {
        let d = p - pose.center;
        let (sin, cos) = pose.yaw.sin_cos();
        let (x, y) = (cos * d.x + sin * d.y, -sin * d.x + cos * d.y);
        x.abs() <= self.size[0] / 2.0 + margin
            && y.abs() <= self.size[1] / 2.0 + margin
            && d.z.abs() <= self.size[2] / 2.0 + margin
    }
}
