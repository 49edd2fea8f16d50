//! The common mistakes students make, which the app and `raylab render --bug` render beside the
//! correct image; the ray caster ([`super::cast`]) switches them on.

use serde::{Deserialize, Serialize};
use strum::{EnumIter, IntoStaticStr};

/// A mistake students make, rendered beside the correct image (in menu order).
#[derive(
    Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, EnumIter, IntoStaticStr,
)]
#[strum(serialize_all = "kebab-case")]
pub enum Bug {
    /// Seed 003's outside test with `and` where `or` is meant.
    AndForOr,
    /// Accepting hits with t < 0.
    NegativeT,
    /// Testing v ≤ 1 instead of β + γ ≤ 1.
    VInsteadOfSum,
    /// Normalising the direction after transforming into object space.
    NormalizedDirection,
    /// Starting shadow (and other secondary) rays exactly at the hit point, without the offset
    /// along the normal: shadow acne.
    ShadowAcne,
}

impl Bug {
    /// The name on the command line (`negative-t`).
    pub fn key(self) -> &'static str {
        self.into()
    }

    /// A short name.
    pub fn name(self) -> &'static str {
        match self {
            Bug::AndForOr => "“and” where “or” is meant",
            Bug::NegativeT => "accepting t < 0",
            Bug::VInsteadOfSum => "v ≤ 1 for β + γ ≤ 1",
            Bug::NormalizedDirection => "normalising D in object space",
            Bug::ShadowAcne => "no offset: shadow acne",
        }
    }

    /// One sentence on the mistake.
    pub fn sentence(self) -> &'static str {
        match self {
            Bug::AndForOr => {
                "Seed 003 calls a point outside only when all three edge tests fail (“and”), but one \
                 failing test is enough (“or”): the whole plane in front of the ray lights up."
            }
            Bug::NegativeT => {
                "Without t > 0 the ray is a line: objects behind the camera are drawn as if in front."
            }
            Bug::VInsteadOfSum => {
                "Checking β ≤ 1 and γ ≤ 1 instead of β + γ ≤ 1 accepts the whole parallelogram \
                 spanned by the triangle's two edges."
            }
            Bug::NormalizedDirection => {
                "After M⁻¹ the direction must stay as it is: normalised, the object-space t is no \
                 longer the world t, so depths and which object is in front go wrong under a \
                 non-uniform scale."
            }
            Bug::ShadowAcne => {
                "The hit point is rounded to one side of the surface or the other: a shadow ray \
                 started exactly there hits its own surface at t ≈ 1e-16 about half the time, and \
                 speckles lit surfaces with shadow. Move the origin off along the normal (or ask \
                 for t > ε)."
            }
        }
    }
}

impl std::str::FromStr for Bug {
    type Err = crate::names::UnknownName;
    fn from_str(key: &str) -> Result<Bug, Self::Err> {
        crate::names::parse("bug", key)
    }
}
