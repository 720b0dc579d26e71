//! The built luminaires: sample k's deviations and its scene.
//!
//! The scalar tolerances take their uniforms from an Owen-scrambled Sobol
//! sequence (one dimension each): sample k is the same luminaire whatever
//! the run's length or split, and the first n samples cover the
//! tolerances' space evenly. A form error takes its standard normals from
//! a ChaCha8 stream keyed by the seed, the sample and the form error.

use lucerna_design::variables;
use lucerna_scene::{Material, Scene};
use rand_chacha::ChaCha8Rng;
use rand_chacha::rand_core::{RngCore, SeedableRng};
use statrs::distribution::{ContinuousCDF, Normal};

use crate::form_error::FormErrorModel;
use crate::tolerances::{At, Tolerances};

/// The Sobol sequence's dimensions: one per scalar tolerance.
pub const MAX_SCALARS: usize = sobol_burley::NUM_DIMENSIONS as usize;

/// The tolerances applied to a nominal scene.
#[derive(Debug, Clone)]
pub struct Model {
    /// The scene as designed.
    pub nominal: Scene,
    pub tolerances: Tolerances,
    pub forms: Vec<FormErrorModel>,
    pub seed: u32,
}

/// One built luminaire's deviations from the nominal.
#[derive(Debug, Clone, PartialEq)]
pub struct Draw {
    pub index: u32,
    /// Each scalar tolerance's deviation (its unit).
    pub deviations: Vec<f64>,
    /// Each form error's uniforms' normals (standard normal numbers).
    pub form_normals: Vec<Vec<f64>>,
    /// Each scalar's uniform number (the Sobol coordinate), for the
    /// sensitivities.
    pub uniforms: Vec<f64>,
}

impl Model {
    pub fn new(nominal: Scene, tolerances: Tolerances, seed: u32) -> Result<Model, String> {
        if tolerances.scalars.len() > MAX_SCALARS {
            return Err(format!(
                "at most {MAX_SCALARS} scalar tolerances, got {}",
                tolerances.scalars.len()
            ));
        }
        let forms = tolerances
            .form_errors
            .iter()
            .map(|f| FormErrorModel::new(&nominal, f))
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Model {
            nominal,
            tolerances,
            forms,
            seed,
        })
    }

    /// Sample `index`'s deviations.
    pub fn draw(&self, index: u32) -> Draw {
        // The sequence holds 2¹⁶ points per scramble: each further block
        // of 2¹⁶ samples is a Sobol set scrambled afresh (randomised
        // quasi-Monte Carlo in blocks), never a point used before.
        let block = index >> 16;
        let scramble = (self.seed.wrapping_mul(0x9E37_79B9) ^ 0x5EED_1E55)
            .wrapping_add(block.wrapping_mul(0x85EB_CA6B))
            .rotate_left(block % 31);
        let uniforms: Vec<f64> = (0..self.tolerances.scalars.len())
            .map(|d| f64::from(sobol_burley::sample(index & 0xFFFF, d as u32, scramble)))
            .collect();
        let deviations = self
            .tolerances
            .scalars
            .iter()
            .zip(&uniforms)
            .map(|(s, &u)| s.distribution.quantile(u))
            .collect();
        let form_normals = self
            .forms
            .iter()
            .enumerate()
            .map(|(k, f)| {
                let mut rng =
                    ChaCha8Rng::seed_from_u64((u64::from(self.seed) << 32) | u64::from(index));
                rng.set_stream(k as u64 + 1);
                (0..f.dimension())
                    .map(|_| standard_normal(rng.next_u64()))
                    .collect()
            })
            .collect();
        Draw {
            index,
            deviations,
            form_normals,
            uniforms,
        }
    }

    /// The nominal's deviations: none.
    pub fn zero(&self) -> Draw {
        Draw {
            index: u32::MAX,
            deviations: vec![0.0; self.tolerances.scalars.len()],
            form_normals: self
                .forms
                .iter()
                .map(|f| vec![0.0; f.dimension()])
                .collect(),
            uniforms: vec![0.5; self.tolerances.scalars.len()],
        }
    }

    /// The form errors' deviations along the normal (m) of a draw.
    pub fn form_deviations(&self, draw: &Draw) -> Vec<Vec<f64>> {
        self.forms
            .iter()
            .zip(&draw.form_normals)
            .map(|(f, z)| f.deviations(z))
            .collect()
    }

    /// The luminaire built with `draw`'s deviations, its surfaces'
    /// slope errors included; why not where a deviation is refused by
    /// the shape (a focal length ≤ 0, a flux ≤ 0).
    pub fn scene(&self, draw: &Draw) -> Result<Scene, String> {
        let mut scene = self.as_built_nominal();
        for (s, &d) in self.tolerances.scalars.iter().zip(&draw.deviations) {
            let value = s.nominal + d;
            match &s.at {
                At::Variable(place) => {
                    variables::set(&mut scene, place, value)
                        .ok_or_else(|| format!("{} = {value} is refused by its shape", s.name))?;
                }
                At::EmitterFlux(i) => {
                    if !(value > 0.0) {
                        return Err(format!("{} = {value}: no light", s.name));
                    }
                    scene.emitters[*i].flux_lm = value;
                }
            }
        }
        for (f, d) in self.forms.iter().zip(self.form_deviations(draw)) {
            f.apply(&mut scene, &d);
        }
        Ok(scene)
    }

    /// The nominal scene with every slope error on its surfaces: the
    /// luminaire as built with no other deviation.
    pub fn as_built_nominal(&self) -> Scene {
        let mut scene = self.nominal.clone();
        for e in &self.tolerances.slope_errors {
            roughen(&mut scene, e.part, e.sigma_rad);
        }
        scene
    }
}

/// Gives part `part` its own copy of its material with a Gaussian slope
/// spread `sigma_rad` (per axis) convolved in: a mirror becomes a rough
/// conductor of GGX α = √2·σ (the Beckmann width of that slope spread,
/// whose core GGX matches), a rough conductor's α grows in quadrature.
pub fn roughen(scene: &mut Scene, part: usize, sigma_rad: f64) {
    let name = scene.parts[part].material.clone();
    let Some(material) = scene.materials.get(&name) else {
        return;
    };
    let extra = std::f64::consts::SQRT_2 * sigma_rad;
    let rough = match material {
        Material::Mirror { reflectance } => Material::RoughConductor {
            reflectance: *reflectance,
            roughness_u: extra,
            roughness_v: extra,
            orientation_deg: 0.0,
        },
        Material::RoughConductor {
            reflectance,
            roughness_u,
            roughness_v,
            orientation_deg,
        } => Material::RoughConductor {
            reflectance: *reflectance,
            roughness_u: roughness_u.hypot(extra),
            roughness_v: roughness_v.hypot(extra),
            orientation_deg: *orientation_deg,
        },
        _ => return,
    };
    let new_name = format!("{name} with slope error ({})", scene.parts[part].name);
    scene.materials.insert(new_name.clone(), rough);
    scene.parts[part].material = new_name;
}

/// A standard normal number from 64 random bits (by the quantile of a
/// uniform in (0, 1)).
pub fn standard_normal(bits: u64) -> f64 {
    let u = ((bits >> 11) as f64 + 0.5) / (1u64 << 53) as f64;
    Normal::standard().inverse_cdf(u)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn samples_past_the_sequences_2_16_points_are_new_points() {
        let scene = lucerna_scene::parse_scene(
            include_str!("../../../assets/luminaires/parabolic_spot.toml"),
            std::path::Path::new("spot.toml"),
        )
        .expect("the example reads");
        let t = crate::tolerances::parse(
            "[[tolerance]]\nat = \"LED.translate_x\"\nuniform = { half_width = 1e-3 }\n\n[[tolerance]]\nat = \"LED.translate_y\"\nuniform = { half_width = 1e-3 }\n",
            &scene,
        )
        .expect("reads");
        let m = Model::new(scene, t, 3).expect("a model");
        for k in [0u32, 1, 7, 12345] {
            assert_ne!(m.draw(k).uniforms, m.draw(k + (1 << 16)).uniforms);
            assert_eq!(m.draw(k), m.draw(k), "sample {k} is one luminaire");
        }
        // Still evenly spread within a block: each half of the x range
        // holds half of the first 1024 samples.
        let low = (0..1024).filter(|&k| m.draw(k).uniforms[0] < 0.5).count();
        assert_eq!(low, 512);
    }
}
