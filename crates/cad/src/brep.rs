//! A body's surfaces as a truck B-rep shell, in millimetres and luminaire
//! coordinates: exact surfaces where the shape states them (a profile
//! revolved, a profile extruded, disks and planar polygons), planar
//! triangles where the traced facets are the surface.

use std::collections::HashMap;
use std::f64::consts::{FRAC_PI_2, FRAC_PI_4};

use glam::{DAffine3, DVec2};
use lucerna_scene::TriangleMesh;
use lucerna_scene::exact::{ExactSurface, ProfileCurve};
use truck_modeling::{
    BSplineCurve, Curve, Edge, Face, KnotVec, Line, Matrix4, NurbsCurve, Plane, Point3, Processor,
    RevolutedCurve, Shell, Surface, Transform, Transformed, Vector3, Vector4, Vertex, Wire,
    builder,
};

/// Scene files are in metres, CAD in millimetres.
pub const MM_PER_M: f64 = 1000.0;

/// Why a body has no B-rep.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum BrepError {
    /// A surface of revolution stretched unequally along its axes is no
    /// longer one, and STEP's surface of revolution cannot hold it.
    #[error(
        "its transform scales unequally ({scale:?}), which turns its surface of revolution into one STEP cannot state exactly; use an equal scale, a faceted shape, or leave it out with --parts"
    )]
    NonUniformScale { scale: [f64; 3] },
    /// The planar face could not be made (the shape passed validation, so
    /// this is a bug or a degenerate polygon).
    #[error("a planar face could not be built: {0}")]
    Plane(String),
}

/// The exact surfaces (part frame, metres) placed by `luminaire_from_part`
/// (metres), as one shell in luminaire millimetres.
pub fn exact_shell(
    surfaces: &[ExactSurface],
    luminaire_from_part: &DAffine3,
) -> Result<Shell, BrepError> {
    let scale = luminaire_from_part.matrix3.to_cols_array_2d().map(|c| {
        let c = glam::DVec3::from_array(c);
        c.length()
    });
    let uniform = (scale[0] - scale[1]).abs() <= 1e-9 * scale[0]
        && (scale[0] - scale[2]).abs() <= 1e-9 * scale[0];
    let mut shell = Shell::new();
    for surface in surfaces {
        match surface {
            ExactSurface::Revolution(curves) => {
                if !uniform {
                    return Err(BrepError::NonUniformScale { scale });
                }
                shell.extend(revolution(curves));
            }
            ExactSurface::Extrusion {
                profile,
                length,
                end_caps,
            } => shell.extend(extrusion(profile, *length, *end_caps)?),
            ExactSurface::Disk { radius, z } => shell.push(disk(*radius, *z)?),
            ExactSurface::Polygon(corners) => {
                let points: Vec<Point3> = corners
                    .iter()
                    .map(|c| Point3::new(c.x, c.y, c.z) * MM_PER_M)
                    .collect();
                shell.push(polygon(&points)?);
            }
        }
    }
    if *luminaire_from_part == DAffine3::IDENTITY {
        Ok(shell)
    } else {
        Ok(builder::transformed(
            &shell,
            millimetre_matrix(luminaire_from_part),
        ))
    }
}

/// The affine map (metres) acting on millimetres: the same linear part,
/// the translation in millimetres.
fn millimetre_matrix(a: &DAffine3) -> Matrix4 {
    let (m, t) = (a.matrix3, a.translation * MM_PER_M);
    Matrix4::new(
        m.x_axis.x, m.x_axis.y, m.x_axis.z, 0.0, //
        m.y_axis.x, m.y_axis.y, m.y_axis.z, 0.0, //
        m.z_axis.x, m.z_axis.y, m.z_axis.z, 0.0, //
        t.x, t.y, t.z, 1.0,
    )
}

/// A profile point (r–z or x–z plane, metres) in millimetres at `y`
/// (metres).
fn point(p: DVec2, y: f64) -> Point3 {
    Point3::new(p.x, y, p.y) * MM_PER_M
}

/// The profile curve at `y` (metres) as truck's exact curve in
/// millimetres: a line, a polynomial Bézier, or a rational one for a
/// conic of weight below 1.
fn curve(curve: &ProfileCurve, y: f64) -> Curve {
    match *curve {
        ProfileCurve::Line { from, to } => Curve::Line(Line(point(from, y), point(to, y))),
        ProfileCurve::Conic {
            from,
            control,
            to,
            weight: 1.0,
        } => {
            let points = vec![point(from, y), point(control, y), point(to, y)];
            Curve::BSplineCurve(BSplineCurve::new(KnotVec::bezier_knot(2), points))
        }
        ProfileCurve::Conic {
            from,
            control,
            to,
            weight,
        } => {
            let homogeneous = |p: DVec2, w: f64| {
                let p = point(p, y);
                Vector4::new(p.x * w, p.y * w, p.z * w, w)
            };
            let points = vec![
                homogeneous(from, 1.0),
                homogeneous(control, weight),
                homogeneous(to, 1.0),
            ];
            Curve::NurbsCurve(NurbsCurve::new(BSplineCurve::new(
                KnotVec::bezier_knot(2),
                points,
            )))
        }
        ProfileCurve::Cubic { points } => {
            let points = points.iter().map(|&p| point(p, y)).collect();
            Curve::BSplineCurve(BSplineCurve::new(KnotVec::bezier_knot(3), points))
        }
    }
}

fn edge(profile_curve: &ProfileCurve, v0: &Vertex, v1: &Vertex, y: f64) -> Edge {
    Edge::new(v0, v1, curve(profile_curve, y))
}

/// The chain of curves as a wire at `y`, consecutive curves sharing their
/// vertex (and the ends one, where the chain closes).
fn wire(curves: &[ProfileCurve], y: f64) -> Wire {
    let mut vertices: Vec<Vertex> = curves
        .iter()
        .map(|c| builder::vertex(point(c.start(), y)))
        .collect();
    let (first, last) = (curves[0].start(), curves[curves.len() - 1].end());
    if curves.len() > 1 && first == last {
        vertices.push(vertices[0].clone());
    } else {
        vertices.push(builder::vertex(point(last, y)));
    }
    curves
        .iter()
        .enumerate()
        .map(|(i, c)| edge(c, &vertices[i], &vertices[i + 1], y))
        .collect()
}

/// A quarter turn about z, `k` times: exact (entries 0 and ±1), so the
/// quarters' seams are the very same points.
fn quarter_turns(k: usize) -> Matrix4 {
    let (c, s) = [(1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0)][k % 4];
    Matrix4::new(
        c, s, 0.0, 0.0, //
        -s, c, 0.0, 0.0, //
        0.0, 0.0, 1.0, 0.0, //
        0.0, 0.0, 0.0, 1.0,
    )
}

/// The quarter circle about z from `p` a quarter turn on, as an exact
/// rational quadratic.
fn quarter_arc(p: Point3) -> Curve {
    let w = FRAC_PI_4.cos();
    // Where the tangents at both ends meet: p and its quarter turn, summed.
    let corner = Point3::new(p.x - p.y, p.y + p.x, p.z);
    let end = Point3::new(-p.y, p.x, p.z);
    Curve::NurbsCurve(NurbsCurve::new(BSplineCurve::new(
        KnotVec::bezier_knot(2),
        vec![
            Vector4::new(p.x, p.y, p.z, 1.0),
            Vector4::new(corner.x * w, corner.y * w, corner.z * w, w),
            Vector4::new(end.x, end.y, end.z, 1.0),
        ],
    )))
}

/// The chain revolved a full turn about z as one sewn shell, each curve
/// in four quarter-turn faces from C0: the surface's extremes along x and
/// y lie on face boundaries, where CAD kernels' bounding boxes are exact
/// (over a turn in thirds OpenCASCADE's box is 1 % too wide). A point of
/// the profile on the axis is a pole: one vertex, no circle of no radius.
fn revolution(curves: &[ProfileCurve]) -> Shell {
    let on_axis = |p: DVec2| p.x == 0.0;
    let mut points: Vec<DVec2> = curves.iter().map(ProfileCurve::start).collect();
    points.push(curves[curves.len() - 1].end());
    let closed = curves.len() > 1 && points[0] == points[points.len() - 1];
    // vertices[j][k]: profile point j a quarter turn k on.
    let mut vertices: Vec<[Vertex; 4]> = points
        .iter()
        .map(|&q| {
            let p = point(q, 0.0);
            if on_axis(q) {
                let pole = builder::vertex(p);
                [pole.clone(), pole.clone(), pole.clone(), pole]
            } else {
                [0, 1, 2, 3].map(|k| builder::vertex(quarter_turns(k).transform_point(p)))
            }
        })
        .collect();
    if closed {
        let first = vertices[0].clone();
        if let Some(last) = vertices.last_mut() {
            *last = first;
        }
    }
    // edges[i][k]: curve i a quarter turn k on; arcs[j][k]: the rim of
    // point j from quarter k to the next.
    let edges: Vec<[Edge; 4]> = curves
        .iter()
        .enumerate()
        .map(|(i, c)| {
            let generatrix = curve(c, 0.0);
            [0, 1, 2, 3].map(|k| {
                Edge::new(
                    &vertices[i][k],
                    &vertices[i + 1][k],
                    generatrix.transformed(quarter_turns(k)),
                )
            })
        })
        .collect();
    let arcs: Vec<Option<[Edge; 4]>> = vertices
        .iter()
        .zip(&points)
        .map(|(v, &q)| {
            (!on_axis(q)).then(|| {
                [0, 1, 2, 3].map(|k| Edge::new(&v[k], &v[(k + 1) % 4], quarter_arc(v[k].point())))
            })
        })
        .collect();
    let mut shell = Shell::new();
    for (i, quarters) in edges.iter().enumerate() {
        for k in 0..4 {
            let mut boundary = Wire::new();
            boundary.push_back(quarters[k].clone());
            if let Some(rim) = &arcs[i + 1] {
                boundary.push_back(rim[k].clone());
            }
            boundary.push_back(quarters[(k + 1) % 4].inverse());
            if let Some(rim) = &arcs[i] {
                boundary.push_back(rim[k].inverse());
            }
            let surface = RevolutedCurve::by_revolution(
                quarters[k].curve(),
                Point3::new(0.0, 0.0, 0.0),
                Vector3::unit_z(),
            );
            shell.push(Face::new(
                vec![boundary],
                Surface::RevolutedCurve(Processor::new(surface)),
            ));
        }
    }
    shell
}

/// The profile swept along y over `length`, centred, with its end caps:
/// the plane region between the profile and its chord.
fn extrusion(profile: &[ProfileCurve], length: f64, end_caps: bool) -> Result<Shell, BrepError> {
    let hy = 0.5 * length;
    let mut shell = builder::tsweep(
        &wire(profile, -hy),
        Vector3::new(0.0, length * MM_PER_M, 0.0),
    );
    if end_caps && encloses_area(profile) {
        for y in [-hy, hy] {
            let mut outline = wire(profile, y);
            if let (false, Some(back), Some(front)) = (
                outline.is_closed(),
                outline.back_vertex(),
                outline.front_vertex(),
            ) {
                let chord = builder::line(back, front);
                outline.push_back(chord);
            }
            let cap = builder::try_attach_plane(&[outline])
                .map_err(|e| BrepError::Plane(e.to_string()))?;
            shell.push(cap);
        }
    }
    Ok(shell)
}

/// Whether the profile and its chord bound a region (the tessellation's
/// rule for end caps: a straight profile has none).
fn encloses_area(profile: &[ProfileCurve]) -> bool {
    let points: Vec<DVec2> = profile
        .iter()
        .flat_map(|c| (0..16).map(move |i| c.point(f64::from(i) / 16.0)))
        .chain(profile.last().map(|c| c.end()))
        .collect();
    let twice_area: f64 = (0..points.len())
        .map(|i| points[i].perp_dot(points[(i + 1) % points.len()]))
        .sum();
    let extent = points
        .iter()
        .map(|p| p.abs().max_element())
        .fold(0.0, f64::max);
    (0.5 * twice_area).abs() > 1e-9 * extent * extent
}

/// A disk about the axis in the plane z = `z` (metres), its rim in
/// quarter circles from C0 (exact bounding boxes, as for revolutions).
fn disk(radius: f64, z: f64) -> Result<Face, BrepError> {
    let at = |angle: f64| Point3::new(radius * angle.cos(), radius * angle.sin(), z) * MM_PER_M;
    let corners: Vec<Vertex> = (0..4)
        .map(|k| builder::vertex(at(f64::from(k) * FRAC_PI_2)))
        .collect();
    let rim: Wire = (0..4)
        .map(|k| {
            let transit = at((f64::from(k) + 0.5) * FRAC_PI_2);
            builder::circle_arc(
                &corners[k as usize],
                &corners[(k as usize + 1) % 4],
                transit,
            )
        })
        .collect();
    builder::try_attach_plane(&[rim]).map_err(|e| BrepError::Plane(e.to_string()))
}

/// A planar polygon through `corners` (millimetres), in order.
fn polygon(corners: &[Point3]) -> Result<Face, BrepError> {
    let vertices: Vec<Vertex> = corners.iter().map(|&c| builder::vertex(c)).collect();
    let outline: Wire = (0..vertices.len())
        .map(|i| builder::line(&vertices[i], &vertices[(i + 1) % vertices.len()]))
        .collect();
    builder::try_attach_plane(&[outline]).map_err(|e| BrepError::Plane(e.to_string()))
}

/// The traced triangles (luminaire coordinates, metres) as planar faces
/// sewn along shared edges: the facets exactly as the tracer sees them.
pub fn triangle_shell(mesh: &TriangleMesh) -> Shell {
    let mut vertex_ids: HashMap<[u32; 3], usize> = HashMap::new();
    let mut vertices: Vec<Vertex> = Vec::new();
    let id_of: Vec<usize> = mesh
        .positions
        .iter()
        .map(|p| {
            let key = p.to_array().map(f32::to_bits);
            *vertex_ids.entry(key).or_insert_with(|| {
                let q = p.as_dvec3() * MM_PER_M;
                vertices.push(builder::vertex(Point3::new(q.x, q.y, q.z)));
                vertices.len() - 1
            })
        })
        .collect();
    let mut edges: HashMap<(usize, usize), Edge> = HashMap::new();
    let mut shell = Shell::new();
    for t in &mesh.triangles {
        let ids = t.map(|i| id_of[i as usize]);
        if ids[0] == ids[1] || ids[1] == ids[2] || ids[0] == ids[2] {
            continue;
        }
        let outline: Wire = (0..3)
            .map(|k| {
                let (a, b) = (ids[k], ids[(k + 1) % 3]);
                let e = edges
                    .entry((a.min(b), a.max(b)))
                    .or_insert_with(|| builder::line(&vertices[a.min(b)], &vertices[a.max(b)]));
                if a < b { e.clone() } else { e.inverse() }
            })
            .collect();
        let [p0, p1, p2] = ids.map(|i| vertices[i].point());
        shell.push(Face::new(
            vec![outline],
            Surface::Plane(Plane::new(p0, p1, p2)),
        ));
    }
    shell
}
