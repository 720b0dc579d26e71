//! The traced triangles as binary STL and as OBJ, in millimetres: the
//! facets the tracer intersects, one OBJ object per body.

use lucerna_scene::TriangleMesh;

use crate::brep::MM_PER_M;

/// Binary STL of every body's triangles (STL has no names: the bodies
/// follow one another in their order).
pub fn stl_bytes(bodies: &[(String, &TriangleMesh)]) -> std::io::Result<Vec<u8>> {
    let triangles: Vec<stl_io::Triangle> = bodies
        .iter()
        .flat_map(|(_, mesh)| {
            (0..mesh.triangle_count()).map(move |t| {
                let corners = mesh.corners(t).map(|c| c * MM_PER_M);
                let normal = mesh.geometric_normal(t).normalize_or_zero().as_vec3();
                stl_io::Triangle {
                    normal: stl_io::Normal::new(normal.to_array()),
                    vertices: corners.map(|c| stl_io::Vertex::new(c.as_vec3().to_array())),
                }
            })
        })
        .collect();
    let mut bytes = Vec::new();
    stl_io::write_stl(&mut bytes, triangles.iter())?;
    Ok(bytes)
}

/// OBJ text of every body's triangles with their shading normals, one
/// object (`o`) per body, named as in the scene.
pub fn obj_text(luminaire: &str, bodies: &[(String, &TriangleMesh)]) -> String {
    use std::fmt::Write;
    let mut out = String::new();
    let one_line = |s: &str| s.replace(['\n', '\r'], " ");
    let _ = writeln!(
        out,
        "# {} by Lucerna {}: millimetres, luminaire coordinates (light leaves towards -z, C0 along +x)",
        one_line(luminaire),
        env!("CARGO_PKG_VERSION")
    );
    let mut first = 1usize;
    for (name, mesh) in bodies {
        let _ = writeln!(out, "o {}", one_line(name));
        for p in &mesh.positions {
            let p = p.as_dvec3() * MM_PER_M;
            let _ = writeln!(out, "v {} {} {}", p.x, p.y, p.z);
        }
        let shaded = mesh.normals.len() == mesh.positions.len();
        if shaded {
            for n in &mesh.normals {
                let _ = writeln!(out, "vn {} {} {}", n.x, n.y, n.z);
            }
        }
        for t in &mesh.triangles {
            let [a, b, c] = t.map(|i| i as usize + first);
            if shaded {
                let _ = writeln!(out, "f {a}//{a} {b}//{b} {c}//{c}");
            } else {
                let _ = writeln!(out, "f {a} {b} {c}");
            }
        }
        first += mesh.positions.len();
    }
    out
}
