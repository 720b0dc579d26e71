//! The sheet's pages: every character they print is in the bundled font
//! (a missing glyph would be a blank box in the PDF), and the same sheet
//! gives the same bytes.

use std::path::Path;

use ab_glyph::{Font, FontRef};
use lucerna_datasheet::{Datasheet, DatasheetOptions, Outdoor};
use lucerna_photometry::read_photometry;

fn sheet(file: &str, outdoor: Outdoor) -> Datasheet {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../assets/profiles")
        .join(file);
    let p = read_photometry(&std::fs::read(&path).expect("file")).expect("photometry");
    Datasheet::new(
        &p,
        &DatasheetOptions {
            ugr_spacings: vec![0.25, 1.0],
            outdoor,
            source_name: file.to_owned(),
        },
    )
    .expect("sheet")
}

fn texts(svg: &str) -> Vec<String> {
    svg.split("<text")
        .skip(1)
        .filter_map(|t| {
            let start = t.find('>')? + 1;
            let end = t.find("</text>")?;
            Some(
                t[start..end]
                    .replace("&lt;", "<")
                    .replace("&gt;", ">")
                    .replace("&quot;", "\"")
                    .replace("&amp;", "&"),
            )
        })
        .collect()
}

#[test]
fn every_character_printed_is_in_the_font() {
    let font = FontRef::try_from_slice(lucerna_pictures::canvas::FONT_TTF).expect("font");
    for (file, outdoor) in [
        ("examples/parabolic_spot.ies", Outdoor::Auto),
        ("examples/linear_louvre.ies", Outdoor::Auto),
        ("samples/rab_roadway1_2002_quadrant.ies", Outdoor::Yes),
        ("samples/erco_33499000_isym2.ldt", Outdoor::No),
    ] {
        let rendered = sheet(file, outdoor).render().expect("renders");
        assert_eq!(rendered.pages.len(), 3);
        for page in &rendered.pages {
            for text in texts(page) {
                for c in text.chars() {
                    assert!(
                        c == ' ' || font.glyph_id(c).0 != 0,
                        "{file}: '{c}' (U+{:04X}) in \"{text}\" has no glyph",
                        c as u32
                    );
                }
            }
        }
        assert!(rendered.pdf.starts_with(b"%PDF-"));
    }
}

#[test]
fn the_same_sheet_gives_the_same_bytes() {
    let a = sheet("examples/opal_bell.ies", Outdoor::Auto)
        .render()
        .expect("renders");
    let b = sheet("examples/opal_bell.ies", Outdoor::Auto)
        .render()
        .expect("renders");
    assert_eq!(a.pdf, b.pdf);
    assert_eq!(a.html, b.html);
}
