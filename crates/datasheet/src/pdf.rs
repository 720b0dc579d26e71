//! The PDF: the same SVG pages the HTML shows, drawn by krilla-svg with
//! the bundled DejaVu Sans embedded as text (selectable, searchable).

use std::sync::{Arc, LazyLock};

use krilla::Document;
use krilla::geom::Size;
use krilla::metadata::Metadata;
use krilla::page::PageSettings;
use krilla_svg::{SurfaceExt, SvgSettings};

use crate::DatasheetError;

/// A font database holding only the project's font, so the PDF looks the
/// same on every machine (no system fonts are consulted).
static FONTS: LazyLock<Arc<usvg::fontdb::Database>> = LazyLock::new(|| {
    let mut db = usvg::fontdb::Database::new();
    db.load_font_data(lucerna_pictures::canvas::FONT_TTF.to_vec());
    db.set_sans_serif_family(crate::svg::FONT_FAMILY);
    Arc::new(db)
});

/// Parses one SVG page with the project's font.
pub(crate) fn parse_page(svg: &str) -> Result<usvg::Tree, DatasheetError> {
    let options = usvg::Options {
        fontdb: FONTS.clone(),
        font_family: crate::svg::FONT_FAMILY.to_owned(),
        ..Default::default()
    };
    usvg::Tree::from_str(svg, &options).map_err(|e| DatasheetError::Svg(e.to_string()))
}

/// The PDF of SVG pages (each page's own size, in points), with a title.
/// No date is written, so the same sheet gives the same bytes.
pub fn pdf_of_pages(pages: &[String], title: &str) -> Result<Vec<u8>, DatasheetError> {
    let mut document = Document::new();
    for svg in pages {
        let tree = parse_page(svg)?;
        let size = Size::from_wh(tree.size().width(), tree.size().height())
            .ok_or_else(|| DatasheetError::Svg("a page has no size".into()))?;
        let mut page = document.start_page_with(PageSettings::new(size));
        let mut surface = page.surface();
        surface
            .draw_svg(&tree, size, SvgSettings::default())
            .ok_or_else(|| DatasheetError::Pdf("a page could not be drawn".into()))?;
        surface.finish();
        page.finish();
    }
    document.set_metadata(
        Metadata::new()
            .title(title.to_owned())
            .creator(format!("Lucerna {}", env!("CARGO_PKG_VERSION"))),
    );
    document
        .finish()
        .map_err(|e| DatasheetError::Pdf(format!("{e:?}")))
}
