//! How surfaces answer a laser: reflectance and how often a beam passes through.

/// The optical properties of a surface, as the sensor model needs them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    /// Diffuse reflectance in [0, 1]: the intensity of a head-on return at short range.
    pub reflectance: f32,
    /// Probability that a beam passes through without a return (glass, foliage gaps).
    pub pass_through: f32,
    /// Whether returns come from inside the volume (foliage) rather than from its surface.
    pub volumetric: bool,
}

impl Material {
    const fn solid(reflectance: f32) -> Self {
        Self {
            reflectance,
            pass_through: 0.0,
            volumetric: false,
        }
    }

    /// Road surface.
    pub const ASPHALT: Self = Self::solid(0.22);
    /// Walls of buildings.
    pub const FACADE: Self = Self::solid(0.35);
    /// Concrete: kerbs, barriers, plinths, benches.
    pub const CONCRETE: Self = Self::solid(0.4);
    /// Painted metal poles and sign posts.
    pub const POLE: Self = Self::solid(0.3);
    /// Galvanised guard rails: bright.
    pub const GUARD_RAIL: Self = Self::solid(0.6);
    /// Retro-reflective sign faces: the brightest returns in a scan.
    pub const SIGN: Self = Self::solid(0.9);
    /// Tree bark.
    pub const BARK: Self = Self::solid(0.28);
    /// Leaves of trees and bushes: returns from inside the crown, many beams pass.
    pub const FOLIAGE: Self = Self {
        reflectance: 0.32,
        pass_through: 0.45,
        volumetric: true,
    };
    /// Car paint.
    pub const PAINT: Self = Self::solid(0.25);
    /// Car windows: dark, and most beams pass.
    pub const GLASS: Self = Self {
        reflectance: 0.08,
        pass_through: 0.6,
        volumetric: false,
    };
    /// Tyres.
    pub const RUBBER: Self = Self::solid(0.05);
    /// Bicycle frames and wheels (thin, so also partly transparent).
    pub const BIKE: Self = Self {
        reflectance: 0.35,
        pass_through: 0.3,
        volumetric: false,
    };
    /// Clothes.
    pub const CLOTH: Self = Self::solid(0.2);
    /// Skin and hair.
    pub const SKIN: Self = Self::solid(0.3);
}
