//! `lucerna validate`: what a scene contains, or why it cannot be used.

use std::fmt;
use std::path::Path;

use anyhow::{Context, Result};
use lucerna_scene::{Emission, EmitterShape, SurfaceKind, load_scene, tessellate};
use serde::Serialize;

#[derive(Debug, Serialize)]
pub struct SurfaceReport {
    name: String,
    kind: &'static str,
    shape: String,
    material: String,
    triangles: usize,
    area_m2: f64,
}

#[derive(Debug, Serialize)]
pub struct ValidateReport {
    name: String,
    triangles: usize,
    bounds_min_m: [f32; 3],
    bounds_max_m: [f32; 3],
    total_flux_lm: f64,
    surfaces: Vec<SurfaceReport>,
    materials: Vec<(String, String)>,
    disabled: Vec<String>,
    /// What the files the scene names say that a user should know (a ray
    /// file whose header and rays disagree).
    warnings: Vec<String>,
}

/// Loads, validates and tessellates; an emission profile referenced by an
/// emitter must exist.
pub fn report(path: &Path) -> Result<ValidateReport> {
    let scene = load_scene(path)?;
    let dir = path.parent().unwrap_or(Path::new("."));
    for e in &scene.emitters {
        if let Emission::Profile(file) = &e.emission {
            let profile = dir.join(file);
            anyhow::ensure!(
                profile.is_file(),
                "emitter '{}': emission profile {} does not exist",
                e.name,
                profile.display()
            );
            super::input::read_photometry(&profile)
                .with_context(|| format!("emitter '{}': unusable emission profile", e.name))?;
        }
    }
    // Every ray file the emitters name, read whole: its header, its size
    // and every record, as a bake will.
    let mut warnings = Vec::new();
    for e in &scene.emitters {
        if let EmitterShape::RayFile { path: file } = &e.shape {
            let rays = dir.join(file);
            let set = super::input::read_rays(&rays)
                .with_context(|| format!("emitter '{}': unusable ray file", e.name))?;
            warnings.extend(
                set.flux_warnings()
                    .into_iter()
                    .map(|w| format!("emitter '{}', {}: {w}", e.name, rays.display())),
            );
        }
    }
    let t = tessellate(&scene, dir)?;
    let (lo, hi) = t.mesh.bounds().unwrap_or_default();
    let surfaces = t
        .surfaces
        .iter()
        .map(|s| {
            let sub = lucerna_scene::TriangleMesh {
                positions: t.mesh.positions.clone(),
                normals: t.mesh.normals.clone(),
                triangles: t.mesh.triangles[s.triangles.clone()].to_vec(),
            };
            let material = t.triangle_material[s.triangles.start] as usize;
            SurfaceReport {
                name: s.name.clone(),
                kind: match s.kind {
                    SurfaceKind::Part => "part",
                    SurfaceKind::Emitter => "emitter",
                },
                shape: match s.kind {
                    SurfaceKind::Part => scene.parts[s.index].shape.kind().to_owned(),
                    SurfaceKind::Emitter => format!("{:?}", scene.emitters[s.index].shape)
                        .split_whitespace()
                        .next()
                        .unwrap_or_default()
                        .to_lowercase(),
                },
                material: t.materials[material].0.clone(),
                triangles: s.triangles.len(),
                area_m2: sub.area(),
            }
        })
        .collect();
    Ok(ValidateReport {
        name: scene.name.clone(),
        triangles: t.triangle_count(),
        bounds_min_m: lo.to_array(),
        bounds_max_m: hi.to_array(),
        total_flux_lm: scene
            .emitters
            .iter()
            .filter(|e| e.enabled)
            .map(|e| e.flux_lm)
            .sum(),
        surfaces,
        materials: t
            .materials
            .iter()
            .map(|(n, m)| (n.clone(), m.kind().to_owned()))
            .collect(),
        disabled: scene
            .parts
            .iter()
            .filter(|p| !p.enabled)
            .map(|p| p.name.clone())
            .chain(
                scene
                    .emitters
                    .iter()
                    .filter(|e| !e.enabled)
                    .map(|e| e.name.clone()),
            )
            .collect(),
        warnings,
    })
}

impl fmt::Display for ValidateReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "scene      {}", self.name)?;
        writeln!(f, "triangles  {}", self.triangles)?;
        let [a, b, c] = self.bounds_min_m.map(|v| v * 1000.0);
        let [x, y, z] = self.bounds_max_m.map(|v| v * 1000.0);
        writeln!(
            f,
            "bounds     x {a:.1}..{x:.1}  y {b:.1}..{y:.1}  z {c:.1}..{z:.1} mm  ({:.1} × {:.1} × {:.1} mm)",
            x - a,
            y - b,
            z - c
        )?;
        writeln!(f, "flux       {:.1} lm", self.total_flux_lm)?;
        writeln!(f, "surfaces")?;
        for s in &self.surfaces {
            writeln!(
                f,
                "  {:<8} {:<20} {:<11} {:<16} {:>8} triangles {:>10.1} cm²",
                s.kind,
                s.name,
                s.shape,
                s.material,
                s.triangles,
                s.area_m2 * 1e4
            )?;
        }
        writeln!(f, "materials")?;
        for (n, k) in &self.materials {
            writeln!(f, "  {n:<20} {k}")?;
        }
        if !self.disabled.is_empty() {
            writeln!(f, "disabled   {}", self.disabled.join(", "))?;
        }
        for w in &self.warnings {
            writeln!(f, "warning    {w}")?;
        }
        writeln!(f, "ok")
    }
}
