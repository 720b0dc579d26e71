//! The datasheet's A4 pages as SVG, and the HTML that shows them.
//!
//! Page 1: luminaire data, polar diagram, photometric figures, zonal
//! lumens and CIE flux code. Page 2: cartesian diagram (narrow beams),
//! isocandela chart, cone diagram, luminance table, BUG rating. Page 3:
//! the UGR table(s). Every section left out says why in its place.

mod diagrams;
mod glare;
mod layout;
mod photometric_data;

use base64::Engine as _;

use crate::Datasheet;
use crate::svg::Svg;

/// The sheet's pages, drawn (`Svg::page` gives each as an SVG document).
pub fn pages(sheet: &Datasheet) -> Vec<Svg> {
    let n = 3;
    vec![
        photometric_data::photometric_data_page(sheet, n),
        diagrams::diagrams_page(sheet, n),
        glare::glare_page(sheet, n),
    ]
}

/// The HTML: the pages inline (text stays text), A4 when printed, the
/// bundled font embedded so it looks the same everywhere.
pub fn html(pages: &[String], title: &str) -> String {
    let font = base64::engine::general_purpose::STANDARD.encode(lucerna_pictures::canvas::FONT_TTF);
    let mut body = String::new();
    for p in pages {
        body.push_str("<section class=\"sheet\">\n");
        body.push_str(p);
        body.push_str("</section>\n");
    }
    format!(
        concat!(
            "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n",
            "<title>{title}</title>\n<style>\n",
            "@font-face {{ font-family: \"DejaVu Sans\"; src: url(data:font/ttf;base64,{font}) format(\"truetype\"); }}\n",
            "@page {{ size: A4; margin: 0; }}\n",
            "body {{ margin: 0; background: #e9ecef; font-family: \"DejaVu Sans\", sans-serif; }}\n",
            ".sheet {{ width: 210mm; height: 297mm; margin: 8mm auto; background: white; box-shadow: 0 1px 4px rgba(0,0,0,.25); }}\n",
            ".sheet svg {{ width: 210mm; height: 297mm; display: block; }}\n",
            "@media print {{ body {{ background: white; }} .sheet {{ margin: 0; box-shadow: none; page-break-after: always; }} }}\n",
            "</style>\n</head>\n<body>\n{body}</body>\n</html>\n"
        ),
        title = crate::svg::escape(title),
        font = font,
        body = body
    )
}
