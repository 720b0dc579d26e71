//! Symmetries of a luminaire about its photometric axis, and what they do to
//! a cube map.
//!
//! The cube map's faces are square about the z axis, so the eight
//! symmetries of a square (quarter turns about z and mirrors in the
//! C0-C180, C90-C270 and diagonal planes, the dihedral group D4) map every
//! texel exactly onto another texel of the same solid angle. A luminaire
//! that has some of these symmetries (most do: a spun reflector has all
//! eight, a linear louvre the two plane mirrors) sends the same intensity
//! into every image of a direction, so the photons counted in a texel's
//! images all estimate its intensity: pooling them is worth tracing
//! |group| times as many photons, at no bias. Arbitrary angles (a 24-facet
//! reflector's 15° turns) do not map texels onto texels and are not used.

use crate::cubemap::{CubeMapLayout, Dir};
use crate::table::CPlaneSymmetry;

/// One of the eight isometries of a square about z, acting on (x, y) of a
/// direction in luminaire coordinates; z is kept.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum AxialIsometry {
    Identity,
    /// Turn by +90° about z: C → C + 90°.
    QuarterTurn,
    /// Turn by 180°: C → C + 180°.
    HalfTurn,
    /// Turn by 270°: C → C + 270°.
    ThreeQuarterTurn,
    /// y → −y: mirror in the C0-C180 plane, C → −C.
    MirrorC0C180,
    /// x → −x: mirror in the C90-C270 plane, C → 180° − C.
    MirrorC90C270,
    /// x ↔ y: mirror in the C45-C225 plane, C → 90° − C.
    MirrorC45C225,
    /// (x, y) → (−y, −x): mirror in the C135-C315 plane, C → 270° − C.
    MirrorC135C315,
}

impl AxialIsometry {
    pub const ALL: [AxialIsometry; 8] = [
        AxialIsometry::Identity,
        AxialIsometry::QuarterTurn,
        AxialIsometry::HalfTurn,
        AxialIsometry::ThreeQuarterTurn,
        AxialIsometry::MirrorC0C180,
        AxialIsometry::MirrorC90C270,
        AxialIsometry::MirrorC45C225,
        AxialIsometry::MirrorC135C315,
    ];

    /// The image of a point or direction (exact: only swaps and signs).
    pub fn apply(self, [x, y, z]: Dir) -> Dir {
        match self {
            AxialIsometry::Identity => [x, y, z],
            AxialIsometry::QuarterTurn => [-y, x, z],
            AxialIsometry::HalfTurn => [-x, -y, z],
            AxialIsometry::ThreeQuarterTurn => [y, -x, z],
            AxialIsometry::MirrorC0C180 => [x, -y, z],
            AxialIsometry::MirrorC90C270 => [-x, y, z],
            AxialIsometry::MirrorC45C225 => [y, x, z],
            AxialIsometry::MirrorC135C315 => [-y, -x, z],
        }
    }

    /// Whether the isometry reverses orientation (a mirror).
    pub fn is_mirror(self) -> bool {
        matches!(
            self,
            AxialIsometry::MirrorC0C180
                | AxialIsometry::MirrorC90C270
                | AxialIsometry::MirrorC45C225
                | AxialIsometry::MirrorC135C315
        )
    }
}

/// A symmetry group of a luminaire about its axis: one of the ten
/// subgroups of the square's symmetries.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum AxialSymmetry {
    /// No symmetry used.
    None,
    /// Mirror in the C0-C180 plane.
    AboutC0C180,
    /// Mirror in the C90-C270 plane.
    AboutC90C270,
    /// Mirror in the C45-C225 plane.
    AboutC45C225,
    /// Mirror in the C135-C315 plane.
    AboutC135C315,
    /// Unchanged by a half turn (C → C + 180°).
    HalfTurn,
    /// Unchanged by quarter turns, without mirrors (a swirl).
    QuarterTurns,
    /// Mirrors in the C0-C180 and C90-C270 planes (quadrant symmetry).
    Quadrant,
    /// Mirrors in the two diagonal planes.
    Diagonals,
    /// All eight: quarter turns and the four mirror planes (every spun
    /// reflector, a square one).
    Square,
}

impl AxialSymmetry {
    /// Every subgroup, largest first.
    pub const ALL: [AxialSymmetry; 10] = [
        AxialSymmetry::Square,
        AxialSymmetry::Quadrant,
        AxialSymmetry::Diagonals,
        AxialSymmetry::QuarterTurns,
        AxialSymmetry::AboutC0C180,
        AxialSymmetry::AboutC90C270,
        AxialSymmetry::AboutC45C225,
        AxialSymmetry::AboutC135C315,
        AxialSymmetry::HalfTurn,
        AxialSymmetry::None,
    ];

    /// The group's isometries, identity first.
    pub fn elements(self) -> Vec<AxialIsometry> {
        use AxialIsometry as I;
        match self {
            AxialSymmetry::None => vec![I::Identity],
            AxialSymmetry::AboutC0C180 => vec![I::Identity, I::MirrorC0C180],
            AxialSymmetry::AboutC90C270 => vec![I::Identity, I::MirrorC90C270],
            AxialSymmetry::AboutC45C225 => vec![I::Identity, I::MirrorC45C225],
            AxialSymmetry::AboutC135C315 => vec![I::Identity, I::MirrorC135C315],
            AxialSymmetry::HalfTurn => vec![I::Identity, I::HalfTurn],
            AxialSymmetry::QuarterTurns => {
                vec![
                    I::Identity,
                    I::QuarterTurn,
                    I::HalfTurn,
                    I::ThreeQuarterTurn,
                ]
            }
            AxialSymmetry::Quadrant => {
                vec![I::Identity, I::HalfTurn, I::MirrorC0C180, I::MirrorC90C270]
            }
            AxialSymmetry::Diagonals => vec![
                I::Identity,
                I::HalfTurn,
                I::MirrorC45C225,
                I::MirrorC135C315,
            ],
            AxialSymmetry::Square => AxialIsometry::ALL.to_vec(),
        }
    }

    /// Number of isometries (how many photons each photon counts for).
    pub fn order(self) -> usize {
        self.elements().len()
    }

    /// The largest group all of whose isometries pass `holds` (checked
    /// per isometry, e.g. against a luminaire's geometry).
    pub fn largest_where(mut holds: impl FnMut(AxialIsometry) -> bool) -> AxialSymmetry {
        let passed: Vec<AxialIsometry> = AxialIsometry::ALL
            .into_iter()
            .filter(|&g| g == AxialIsometry::Identity || holds(g))
            .collect();
        AxialSymmetry::ALL
            .into_iter()
            .find(|s| s.elements().iter().all(|g| passed.contains(g)))
            .unwrap_or(AxialSymmetry::None)
    }

    /// The largest symmetry an IES or LDT file can declare for it.
    pub fn file_symmetry(self) -> CPlaneSymmetry {
        match self {
            AxialSymmetry::Square | AxialSymmetry::Quadrant => CPlaneSymmetry::Quadrant,
            AxialSymmetry::AboutC0C180 => CPlaneSymmetry::AboutC0C180,
            AxialSymmetry::AboutC90C270 => CPlaneSymmetry::AboutC90C270,
            _ => CPlaneSymmetry::None,
        }
    }

    pub fn describe(self) -> &'static str {
        match self {
            AxialSymmetry::None => "none",
            AxialSymmetry::AboutC0C180 => "mirror in the C0-C180 plane (2)",
            AxialSymmetry::AboutC90C270 => "mirror in the C90-C270 plane (2)",
            AxialSymmetry::AboutC45C225 => "mirror in the C45-C225 plane (2)",
            AxialSymmetry::AboutC135C315 => "mirror in the C135-C315 plane (2)",
            AxialSymmetry::HalfTurn => "half turn (2)",
            AxialSymmetry::QuarterTurns => "quarter turns (4)",
            AxialSymmetry::Quadrant => "mirrors in the C0-C180 and C90-C270 planes (4)",
            AxialSymmetry::Diagonals => "mirrors in the two diagonal planes (4)",
            AxialSymmetry::Square => "quarter turns and four mirror planes (8)",
        }
    }
}

impl std::fmt::Display for AxialSymmetry {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.describe())
    }
}

/// A symmetry group acting on the texels of one cube-map layout: for every
/// isometry but the identity, the texel each texel maps onto.
#[derive(Debug, Clone, PartialEq)]
pub struct TexelSymmetry {
    pub symmetry: AxialSymmetry,
    pub layout: CubeMapLayout,
    /// `images[g − 1][t]`: the texel the group's isometry g (≥ 1) maps
    /// texel t onto; the identity is implicit, so no symmetry costs nothing.
    images: Vec<Vec<u32>>,
}

impl TexelSymmetry {
    /// The permutations of `layout`'s texels. Texel centres map onto texel
    /// centres exactly (the isometries only swap and negate coordinates),
    /// so the lookup by direction is exact.
    pub fn new(layout: CubeMapLayout, symmetry: AxialSymmetry) -> TexelSymmetry {
        let images = symmetry
            .elements()
            .into_iter()
            .filter(|&g| g != AxialIsometry::Identity)
            .map(|g| {
                (0..layout.texel_count())
                    .map(|t| {
                        let image = g.apply(layout.texel_centre_direction(t));
                        layout.texel_of_direction(image) as u32
                    })
                    .collect()
            })
            .collect();
        TexelSymmetry {
            symmetry,
            layout,
            images,
        }
    }

    /// No symmetry: pooling is the identity.
    pub fn none(layout: CubeMapLayout) -> TexelSymmetry {
        TexelSymmetry::new(layout, AxialSymmetry::None)
    }

    /// Number of isometries, the identity included.
    pub fn order(&self) -> usize {
        self.images.len() + 1
    }

    /// The image of texel `t` under the group's isometry `g` (0: identity,
    /// in the order of [`AxialSymmetry::elements`]).
    pub fn image(&self, g: usize, t: usize) -> usize {
        match g {
            0 => t,
            g => self.images[g - 1][t] as usize,
        }
    }

    /// Sum of the counts of every image of each texel, one term per
    /// isometry: the counts a bake with `order()` times the photons would
    /// give in expectation (its photons are each photon's images). Texels
    /// that an isometry maps onto themselves count those photons once per
    /// such isometry, so the total is exactly `order()` × the input total.
    pub fn pool(&self, counts: &[u64]) -> Vec<u64> {
        debug_assert_eq!(counts.len(), self.layout.texel_count());
        (0..counts.len())
            .map(|t| {
                counts[t]
                    + self
                        .images
                        .iter()
                        .map(|g| counts[g[t] as usize])
                        .sum::<u64>()
            })
            .collect()
    }

    /// How many isometries map texel `t` onto itself. A pooled count is
    /// that many times a sum of independent counts, so its variance is
    /// `multiplicity × count` rather than `count`.
    pub fn multiplicity(&self, t: usize) -> usize {
        1 + self.images.iter().filter(|g| g[t] as usize == t).count()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_group_is_closed_under_composition() {
        for s in AxialSymmetry::ALL {
            let elements = s.elements();
            for &g in &elements {
                for &h in &elements {
                    let p = [0.3, 0.7, 0.1];
                    let gh = g.apply(h.apply(p));
                    assert!(
                        elements.iter().any(|k| k.apply(p) == gh),
                        "{s:?}: {g:?}∘{h:?} is not in the group"
                    );
                }
            }
        }
    }

    #[test]
    fn the_largest_group_is_found_from_its_generators() {
        use AxialIsometry as I;
        let only = |set: &'static [AxialIsometry]| move |g| set.contains(&g);
        assert_eq!(
            AxialSymmetry::largest_where(|_| true),
            AxialSymmetry::Square
        );
        assert_eq!(AxialSymmetry::largest_where(|_| false), AxialSymmetry::None);
        assert_eq!(
            AxialSymmetry::largest_where(only(&[I::MirrorC0C180, I::MirrorC90C270, I::HalfTurn])),
            AxialSymmetry::Quadrant
        );
        // Two mirrors without the half turn they compose to are not a
        // group: one mirror is.
        assert_eq!(
            AxialSymmetry::largest_where(only(&[I::MirrorC0C180, I::MirrorC90C270])),
            AxialSymmetry::AboutC0C180
        );
    }
}
