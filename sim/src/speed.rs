//! Speed over time: phases of constant acceleration, giving distance, speed and acceleration
//! at any time exactly.

/// Distance, speed and acceleration along a path at one time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Progress {
    /// Distance travelled since time 0 (metres; negative before it).
    pub s: f64,
    /// Speed (m/s).
    pub v: f64,
    /// Longitudinal acceleration (m/s²).
    pub a: f64,
}

/// One phase of constant acceleration.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Phase {
    t0: f64,
    s0: f64,
    v0: f64,
    a: f64,
    duration: f64,
}

/// A speed profile: before time 0 the initial speed, then phases of constant acceleration,
/// then the final speed for ever.
#[derive(Clone, Debug, PartialEq)]
pub struct SpeedProfile {
    v0: f64,
    phases: Vec<Phase>,
}

impl SpeedProfile {
    /// A constant speed.
    pub fn constant(v: f64) -> Self {
        Self {
            v0: v,
            phases: Vec::new(),
        }
    }

    /// Starts building a profile at speed `v0` at time 0.
    pub fn starting(v0: f64) -> SpeedBuilder {
        SpeedBuilder {
            v0,
            v: v0,
            pieces: Vec::new(),
        }
    }

    /// Distance, speed and acceleration at time `t`.
    pub fn at(&self, t: f64) -> Progress {
        if t <= 0.0 {
            return Progress {
                s: self.v0 * t,
                v: self.v0,
                a: 0.0,
            };
        }
        let i = self.phases.partition_point(|p| p.t0 <= t);
        let Some(p) = i.checked_sub(1).map(|i| &self.phases[i]) else {
            return Progress {
                s: self.v0 * t,
                v: self.v0,
                a: 0.0,
            };
        };
        let u = t - p.t0;
        if u <= p.duration {
            return Progress {
                s: p.s0 + p.v0 * u + 0.5 * p.a * u * u,
                v: p.v0 + p.a * u,
                a: p.a,
            };
        }
        // After the last phase: its final speed.
        let d = p.duration;
        let v_end = p.v0 + p.a * d;
        Progress {
            s: p.s0 + p.v0 * d + 0.5 * p.a * d * d + v_end * (u - d),
            v: v_end,
            a: 0.0,
        }
    }
}

/// Builds a [`SpeedProfile`] phase by phase.
#[derive(Clone, Debug)]
pub struct SpeedBuilder {
    v0: f64,
    v: f64,
    /// (duration, acceleration) of each phase.
    pieces: Vec<(f64, f64)>,
}

impl SpeedBuilder {
    /// Keeps the current speed for `duration` seconds.
    pub fn hold(mut self, duration: f64) -> Self {
        self.pieces.push((duration, 0.0));
        self
    }

    /// Changes speed to `v` at `accel` m/s² (magnitude).
    pub fn to(mut self, v: f64, accel: f64) -> Self {
        let dv = v - self.v;
        if dv.abs() > 1e-12 && accel > 0.0 {
            self.pieces.push((dv.abs() / accel, accel * dv.signum()));
            self.v = v;
        }
        self
    }

    /// The speed reached so far.
    pub fn speed(&self) -> f64 {
        self.v
    }

    /// The finished profile.
    pub fn build(self) -> SpeedProfile {
        let mut phases = Vec::with_capacity(self.pieces.len());
        let (mut t0, mut s0, mut v0) = (0.0, 0.0, self.v0);
        for (duration, a) in self.pieces {
            if duration <= 0.0 {
                continue;
            }
            phases.push(Phase {
                t0,
                s0,
                v0,
                a,
                duration,
            });
            s0 += v0 * duration + 0.5 * a * duration * duration;
            v0 += a * duration;
            t0 += duration;
        }
        SpeedProfile {
            v0: self.v0,
            phases,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stop_and_go() {
        let p = SpeedProfile::starting(10.0)
            .hold(1.0)
            .to(0.0, 5.0)
            .hold(2.0)
            .to(4.0, 2.0)
            .build();
        assert_eq!(p.at(0.5).s, 5.0);
        // Braking 2 s from 10 m/s covers 10 m.
        let stopped = p.at(3.5);
        assert!((stopped.s - 20.0).abs() < 1e-12 && stopped.v == 0.0);
        let go = p.at(6.0);
        assert!((go.v - 2.0).abs() < 1e-12 && go.a == 2.0);
        let after = p.at(10.0);
        assert!((after.v - 4.0).abs() < 1e-12 && after.a == 0.0);
        assert!((after.s - (20.0 + 4.0 + 4.0 * 3.0)).abs() < 1e-12);
        assert_eq!(p.at(-1.0).s, -10.0);
    }

    #[test]
    fn distance_is_the_integral_of_speed() {
        let p = SpeedProfile::starting(3.0)
            .to(8.0, 1.5)
            .hold(2.0)
            .to(5.0, 3.0)
            .build();
        let dt = 1e-4;
        let mut s = 0.0;
        let mut t = 0.0;
        while t < 9.0 {
            s += p.at(t + dt / 2.0).v * dt;
            t += dt;
        }
        assert!((s - p.at(t).s).abs() < 1e-6);
    }
}
