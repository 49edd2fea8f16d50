//! What accuracy costs in time: the intersection methods of [`crate::intersect`], each in f32 and f64,
//! judged against the exact rational solver on seeded families of easy and hard rays ([`study`]), and the
//! gallery of hard cases ([`hard_cases`]).

pub mod families;
pub mod hard_cases;
pub mod study;
