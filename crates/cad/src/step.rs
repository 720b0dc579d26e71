//! The STEP file (ISO 10303-21, AP214 automotive design): truck writes the
//! B-rep entities; this module gives the file its header, names the
//! product after the luminaire and each body after its part.

use truck_modeling::Shell;
use truck_stepio::out::StepModels;

/// The STEP file of `bodies` (name, shell in millimetres) as an assembly:
/// the luminaire is the top product and each body a product of its own
/// under its name, holding one shell-based surface model, placed without
/// a transformation (the shells are already in luminaire coordinates).
/// Names on products are what CAD tools show in their model trees.
pub fn step_text(luminaire: &str, file_name: &str, bodies: &[(String, String, Shell)]) -> String {
    let compressed: Vec<_> = bodies
        .iter()
        .map(|(_, _, shell)| shell.compress())
        .collect();
    let models: StepModels<_, _, _> = compressed.iter().collect();
    let data = models.to_string();
    let luminaire = step_string(luminaire);
    let version = env!("CARGO_PKG_VERSION");
    let mut out = String::with_capacity(data.len() + 1024 * (bodies.len() + 1));
    out.push_str("ISO-10303-21;\nHEADER;\n");
    out.push_str(
        "FILE_DESCRIPTION(('Lucerna luminaire geometry in millimetres, luminaire coordinates: light leaves towards -z, C0 along +x'),'2;1');\n",
    );
    out.push_str(&format!(
        "FILE_NAME({},'',(''),(''),'Lucerna {version}','Lucerna {version} (truck-stepio)','');\n",
        step_string(file_name)
    ));
    out.push_str("FILE_SCHEMA(('AUTOMOTIVE_DESIGN { 1 0 10303 214 1 1 1 1 }'));\nENDSEC;\nDATA;\n");
    // truck numbers the header entities #1-#15 (#5 the product
    // definition, #8 and #9 its contexts, #10 the representation, #11 its
    // context) and then each model: "#N = SHELL_BASED_SURFACE_MODEL".
    let mut model_ids = Vec::new();
    let mut last_id = 0usize;
    for line in data.lines() {
        if let Some(id) = line
            .strip_prefix('#')
            .and_then(|l| l.split_once(' '))
            .and_then(|(id, _)| id.parse::<usize>().ok())
        {
            last_id = last_id.max(id);
        }
        if let Some(rest) = line.strip_prefix("#7 = PRODUCT('','','', ") {
            out.push_str(&format!("#7 = PRODUCT({luminaire},{luminaire},'', {rest}"));
        } else if line.starts_with("#10 = ADVANCED_BREP_SHAPE_REPRESENTATION(") {
            // The assembly's own representation holds only its origin.
            out.push_str(&format!(
                "#10 = SHAPE_REPRESENTATION({luminaire}, (#{}), #11);",
                last_id_placeholder()
            ));
        } else if let Some((head, rest)) = line.split_once(" = SHELL_BASED_SURFACE_MODEL('', ") {
            let name = step_string(&bodies[model_ids.len().min(bodies.len() - 1)].0);
            model_ids.push(head.trim_start_matches('#').to_owned());
            out.push_str(&format!(
                "{head} = SHELL_BASED_SURFACE_MODEL({name}, {rest}"
            ));
        } else {
            out.push_str(line);
        }
        out.push('\n');
    }
    let mut next = last_id + 1;
    let mut id = || {
        next += 1;
        next - 1
    };
    let placement = |out: &mut String, id: &mut dyn FnMut() -> usize| -> usize {
        let (p, o, z, x) = (id(), id(), id(), id());
        out.push_str(&format!(
            "#{p} = AXIS2_PLACEMENT_3D('', #{o}, #{z}, #{x});\n#{o} = CARTESIAN_POINT('', (0.0, 0.0, 0.0));\n#{z} = DIRECTION('', (0.0, 0.0, 1.0));\n#{x} = DIRECTION('', (1.0, 0.0, 0.0));\n"
        ));
        p
    };
    let root_origin = placement(&mut out, &mut id);
    for ((name, description, _), model) in bodies.iter().zip(&model_ids) {
        let name = step_string(name);
        let description = step_string(description);
        let origin = placement(&mut out, &mut id);
        let (product, formation, definition, shape, sdr, rep) =
            (id(), id(), id(), id(), id(), id());
        let (nauo, nauo_shape, cdsr, relation, transform) = (id(), id(), id(), id(), id());
        out.push_str(&format!(
            "#{product} = PRODUCT({name},{name},{description}, (#8));\n\
#{formation} = PRODUCT_DEFINITION_FORMATION('','', #{product});\n\
#{definition} = PRODUCT_DEFINITION('design','', #{formation}, #9);\n\
#{shape} = PRODUCT_DEFINITION_SHAPE('','', #{definition});\n\
#{sdr} = SHAPE_DEFINITION_REPRESENTATION(#{shape}, #{rep});\n\
#{rep} = MANIFOLD_SURFACE_SHAPE_REPRESENTATION({name}, (#{model}, #{origin}), #11);\n\
#{nauo} = NEXT_ASSEMBLY_USAGE_OCCURRENCE('{nauo}',{name},'', #5, #{definition}, $);\n\
#{nauo_shape} = PRODUCT_DEFINITION_SHAPE('','', #{nauo});\n\
#{cdsr} = CONTEXT_DEPENDENT_SHAPE_REPRESENTATION(#{relation}, #{nauo_shape});\n\
#{relation} = ( REPRESENTATION_RELATIONSHIP('','', #{rep}, #10) REPRESENTATION_RELATIONSHIP_WITH_TRANSFORMATION(#{transform}) SHAPE_REPRESENTATION_RELATIONSHIP() );\n\
#{transform} = ITEM_DEFINED_TRANSFORMATION('','', #{origin}, #{root_origin});\n"
        ));
    }
    out = out.replace(
        &format!("(#{}), #11);", last_id_placeholder()),
        &format!("(#{root_origin}), #11);"),
    );
    out.push_str("ENDSEC;\nEND-ISO-10303-21;\n");
    out
}

/// Stands in for the root placement's number until it is known.
fn last_id_placeholder() -> &'static str {
    "ROOT_ORIGIN"
}

/// `s` as a STEP string literal: quotes doubled, backslashes doubled,
/// anything beyond printable ASCII as `\X2\` UTF-16 (`\X4\` beyond the
/// basic plane), as ISO 10303-21 spells them.
pub fn step_string(s: &str) -> String {
    let mut out = String::from("'");
    for c in s.chars() {
        match c {
            '\'' => out.push_str("''"),
            '\\' => out.push_str("\\\\"),
            ' '..='~' => out.push(c),
            c if (c as u32) <= 0xFFFF => out.push_str(&format!("\\X2\\{:04X}\\X0\\", c as u32)),
            c => out.push_str(&format!("\\X4\\{:08X}\\X0\\", c as u32)),
        }
    }
    out.push('\'');
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn step_strings_escape_quotes_backslashes_and_non_ascii() {
        assert_eq!(step_string("Spot"), "'Spot'");
        assert_eq!(step_string("it's"), "'it''s'");
        assert_eq!(step_string("a\\b"), "'a\\\\b'");
        assert_eq!(step_string("Ø 50"), "'\\X2\\00D8\\X0\\ 50'");
        assert_eq!(step_string("\u{1F4A1}"), "'\\X4\\0001F4A1\\X0\\'");
    }
}
