//! Shading: what happens after a hit — the colour the scene's effects call for, the lights, the
//! optics of mirrors and glass, and the seeded samples of the effects past ray casting.

pub mod light;
pub mod optics;
pub mod sampling;
pub mod shade;
