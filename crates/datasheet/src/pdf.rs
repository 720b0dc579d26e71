//! The PDF: the pages' elements, the same ones the SVG shows, written with
//! pdf-writer. Text is set in the bundled DejaVu Sans, embedded whole (it
//! is already a 106 kB subset) as a CID font with a ToUnicode map, so it
//! stays selectable and searchable; glyphs are placed with the advances
//! and kerning the layout measured, so columns line up as in the SVG.
//!
//! Written directly rather than through an SVG renderer: the sheet draws
//! five kinds of element, and krilla with krilla-svg, usvg and a font
//! subsetter cost about a sixth of a fresh build's compile time.

use std::collections::{BTreeMap, BTreeSet};

use ab_glyph::{Font, FontRef, GlyphId};
use pdf_writer::types::{CidFontType, FontFlags, LineJoinStyle, SystemInfo, UnicodeCmap};
use pdf_writer::{Content, Filter, Finish, Name, Pdf, Rect, Ref, Str, TextStr};

use crate::DatasheetError;
use crate::svg::{Element, PAGE_HEIGHT_PT, PAGE_WIDTH_PT, Rgb, Svg};

const FONT_RESOURCE: Name<'static> = Name(b"F1");
const BASE_FONT: Name<'static> = Name(b"DejaVuSans");
/// Bézier handle length of a quarter circle, as a fraction of its radius.
const KAPPA: f64 = 0.552_284_75;

/// The PDF of the pages (A4, in points), with a title. No date is
/// written, so the same sheet gives the same bytes.
pub fn pdf_of_pages(pages: &[Svg], title: &str) -> Result<Vec<u8>, DatasheetError> {
    let font = lucerna_pictures::canvas::font()
        .ok_or_else(|| DatasheetError::Pdf("the bundled font does not parse".into()))?;
    let mut ids = Ids(0);
    let catalog = ids.next();
    let page_tree = ids.next();
    let info = ids.next();
    let fonts = FontRefs {
        type0: ids.next(),
        cid: ids.next(),
        descriptor: ids.next(),
        file: ids.next(),
        to_unicode: ids.next(),
    };
    let opacities = opacities(pages);
    let states: Vec<Ref> = opacities.iter().map(|_| ids.next()).collect();
    let page_ids: Vec<(Ref, Ref)> = pages.iter().map(|_| (ids.next(), ids.next())).collect();

    let mut pdf = Pdf::new();
    pdf.catalog(catalog).pages(page_tree);
    pdf.pages(page_tree)
        .kids(page_ids.iter().map(|(page, _)| *page))
        .count(i32::try_from(pages.len()).unwrap_or(i32::MAX));
    pdf.document_info(info)
        .title(TextStr(title))
        .creator(TextStr(&format!("Lucerna {}", env!("CARGO_PKG_VERSION"))));

    let mut glyphs = BTreeMap::new();
    for (svg, (page_id, content_id)) in pages.iter().zip(&page_ids) {
        let content = page_content(svg, &opacities, &mut glyphs);
        let compressed = deflate(&content.finish());
        pdf.stream(*content_id, &compressed)
            .filter(Filter::FlateDecode);
        let mut page = pdf.page(*page_id);
        page.parent(page_tree)
            .media_box(Rect::new(
                0.0,
                0.0,
                PAGE_WIDTH_PT as f32,
                PAGE_HEIGHT_PT as f32,
            ))
            .contents(*content_id);
        let mut resources = page.resources();
        resources.fonts().pair(FONT_RESOURCE, fonts.type0);
        let mut gs = resources.ext_g_states();
        for (i, state) in states.iter().enumerate() {
            gs.pair(Name(state_name(i).as_bytes()), *state);
        }
    }
    for (opacity, state) in opacities.iter().zip(&states) {
        pdf.ext_graphics(*state)
            .non_stroking_alpha(f32::from_bits(*opacity));
    }
    write_font(&mut pdf, font, &fonts, &glyphs);
    Ok(pdf.finish())
}

/// Consecutive object numbers.
struct Ids(i32);

impl Ids {
    fn next(&mut self) -> Ref {
        self.0 += 1;
        Ref::new(self.0)
    }
}

struct FontRefs {
    type0: Ref,
    cid: Ref,
    descriptor: Ref,
    file: Ref,
    to_unicode: Ref,
}

/// The fill opacities the polygons use (as f32 bits, so they sort and
/// compare exactly), one graphics state each.
fn opacities(pages: &[Svg]) -> Vec<u32> {
    let set: BTreeSet<u32> = pages
        .iter()
        .flat_map(|p| p.elements())
        .filter_map(|e| match e {
            Element::Polygon { opacity, .. } => Some((opacity.clamp(0.0, 1.0) as f32).to_bits()),
            _ => None,
        })
        .collect();
    set.into_iter().collect()
}

fn state_name(i: usize) -> String {
    format!("GS{i}")
}

/// One page's drawing operators. The page is flipped once so that y runs
/// down from the top, as the elements have it; text is flipped back.
fn page_content(svg: &Svg, opacities: &[u32], glyphs: &mut BTreeMap<u16, char>) -> Content {
    let mut c = Content::new();
    c.transform([1.0, 0.0, 0.0, -1.0, 0.0, PAGE_HEIGHT_PT as f32]);
    for element in svg.elements() {
        match element {
            Element::Text {
                x,
                y,
                size,
                anchor,
                fill,
                text,
            } => {
                let (run, width_em) = lucerna_pictures::canvas::glyph_run_em(text);
                if run.is_empty() {
                    continue;
                }
                let width_em = f64::from(width_em);
                let x0 = x - anchor.offset_fraction() * width_em * size;
                set_fill(&mut c, *fill);
                c.begin_text();
                c.set_font(FONT_RESOURCE, *size as f32);
                c.set_text_matrix([1.0, 0.0, 0.0, -1.0, x0 as f32, *y as f32]);
                show_run(&mut c, text, &run, glyphs);
                c.end_text();
            }
            Element::Polyline {
                points,
                stroke,
                width,
                dash,
            } => {
                set_stroke(&mut c, *stroke, *width);
                c.set_dash_pattern(dash.iter().map(|&d| d as f32), 0.0);
                c.set_line_join(LineJoinStyle::RoundJoin);
                path(&mut c, points);
                c.stroke();
                c.set_dash_pattern([], 0.0);
                c.set_line_join(LineJoinStyle::MiterJoin);
            }
            Element::Rect {
                x,
                y,
                w,
                h,
                fill,
                stroke,
            } => {
                set_fill(&mut c, *fill);
                set_stroke(&mut c, *stroke, 0.5);
                c.rect(*x as f32, *y as f32, *w as f32, *h as f32);
                c.fill_nonzero_and_stroke();
            }
            Element::Circle {
                cx,
                cy,
                r,
                stroke,
                width,
            } => {
                set_stroke(&mut c, *stroke, *width);
                circle(&mut c, *cx, *cy, *r);
                c.stroke();
            }
            Element::Polygon {
                points,
                fill,
                opacity,
            } => {
                let bits = (opacity.clamp(0.0, 1.0) as f32).to_bits();
                let Some(state) = opacities.iter().position(|&o| o == bits) else {
                    continue;
                };
                c.save_state();
                c.set_parameters(Name(state_name(state).as_bytes()));
                set_fill(&mut c, *fill);
                path(&mut c, points);
                c.close_path();
                c.fill_nonzero();
                c.restore_state();
            }
        }
    }
    c
}

fn set_fill(c: &mut Content, colour: Rgb) {
    let [r, g, b] = colour.unit();
    c.set_fill_rgb(r, g, b);
}

fn set_stroke(c: &mut Content, colour: Rgb, width: f64) {
    let [r, g, b] = colour.unit();
    c.set_stroke_rgb(r, g, b);
    c.set_line_width(width as f32);
}

fn path(c: &mut Content, points: &[[f64; 2]]) {
    for (i, p) in points.iter().enumerate() {
        if i == 0 {
            c.move_to(p[0] as f32, p[1] as f32);
        } else {
            c.line_to(p[0] as f32, p[1] as f32);
        }
    }
}

/// A circle as four cubic Béziers (0.03 % from round at most).
fn circle(c: &mut Content, cx: f64, cy: f64, r: f64) {
    let k = KAPPA * r;
    let p = |x: f64, y: f64| ((cx + x) as f32, (cy + y) as f32);
    let (x, y) = p(r, 0.0);
    c.move_to(x, y);
    for [(ax, ay), (bx, by), (ex, ey)] in [
        [(r, k), (k, r), (0.0, r)],
        [(-k, r), (-r, k), (-r, 0.0)],
        [(-r, -k), (-k, -r), (0.0, -r)],
        [(k, -r), (r, -k), (r, 0.0)],
    ] {
        let (x1, y1) = p(ax, ay);
        let (x2, y2) = p(bx, by);
        let (x3, y3) = p(ex, ey);
        c.cubic_to(x1, y1, x2, y2, x3, y3);
    }
    c.close_path();
}

/// Shows a glyph run as two-byte glyph ids (Identity-H), moving each
/// glyph to the pen position the layout gave it where the font's own
/// advance would put it elsewhere (kerning). Records each glyph's
/// character for the ToUnicode map.
fn show_run(c: &mut Content, text: &str, run: &[(GlyphId, f32)], glyphs: &mut BTreeMap<u16, char>) {
    let Some(font) = lucerna_pictures::canvas::font() else {
        return;
    };
    let em = font.units_per_em().unwrap_or(2048.0);
    let mut shown = c.show_positioned();
    let mut items = shown.items();
    let mut pen_em = 0.0f32;
    for ((id, x_em), ch) in run.iter().zip(text.chars()) {
        let adjust = x_em - pen_em;
        if adjust.abs() > 1e-6 {
            // TJ's numbers move the pen left, in thousandths of an em.
            items.adjust(-adjust * 1000.0);
        }
        glyphs.entry(id.0).or_insert(ch);
        items.show(Str(&id.0.to_be_bytes()));
        pen_em = x_em + font.h_advance_unscaled(*id) / em;
    }
}

/// The Type 0 font over the embedded TrueType program: widths of the
/// glyphs shown, the font's metrics and the map back to Unicode.
fn write_font(
    pdf: &mut Pdf,
    font: &FontRef<'static>,
    refs: &FontRefs,
    glyphs: &BTreeMap<u16, char>,
) {
    let em = font.units_per_em().unwrap_or(2048.0);
    let to_pdf = |units: f32| units / em * 1000.0;
    let system_info = SystemInfo {
        registry: Str(b"Adobe"),
        ordering: Str(b"Identity"),
        supplement: 0,
    };
    pdf.type0_font(refs.type0)
        .base_font(BASE_FONT)
        .encoding_predefined(Name(b"Identity-H"))
        .descendant_font(refs.cid)
        .to_unicode(refs.to_unicode);
    let mut cid = pdf.cid_font(refs.cid);
    cid.subtype(CidFontType::Type2)
        .base_font(BASE_FONT)
        .system_info(system_info)
        .font_descriptor(refs.descriptor)
        .default_width(to_pdf(font.h_advance_unscaled(GlyphId(0))))
        .cid_to_gid_map_predefined(Name(b"Identity"));
    {
        let mut widths = cid.widths();
        for &gid in glyphs.keys() {
            widths.consecutive(gid, [to_pdf(font.h_advance_unscaled(GlyphId(gid)))]);
        }
    }
    cid.finish();

    // The box around every glyph shown (the descriptor's FontBBox).
    let mut bbox = [
        0.0f32,
        to_pdf(font.descent_unscaled()),
        0.0,
        to_pdf(font.ascent_unscaled()),
    ];
    for &gid in glyphs.keys() {
        if let Some(outline) = font.outline(GlyphId(gid)) {
            bbox[0] = bbox[0].min(to_pdf(outline.bounds.min.x));
            bbox[1] = bbox[1].min(to_pdf(outline.bounds.min.y));
            bbox[2] = bbox[2].max(to_pdf(outline.bounds.max.x));
            bbox[3] = bbox[3].max(to_pdf(outline.bounds.max.y));
        }
    }
    let cap_height = font
        .outline(font.glyph_id('H'))
        .map_or(729.0, |o| to_pdf(o.bounds.max.y));
    pdf.font_descriptor(refs.descriptor)
        .name(BASE_FONT)
        .flags(FontFlags::NON_SYMBOLIC)
        .bbox(Rect::new(bbox[0], bbox[1], bbox[2], bbox[3]))
        .italic_angle(0.0)
        .ascent(to_pdf(font.ascent_unscaled()))
        .descent(to_pdf(font.descent_unscaled()))
        .cap_height(cap_height)
        .stem_v(80.0)
        .font_file2(refs.file);

    let program = lucerna_pictures::canvas::FONT_TTF;
    let compressed = deflate(program);
    pdf.stream(refs.file, &compressed)
        .filter(Filter::FlateDecode)
        .pair(
            Name(b"Length1"),
            i32::try_from(program.len()).unwrap_or(i32::MAX),
        );

    let mut cmap = UnicodeCmap::new(Name(b"Lucerna-UTF16"), system_info);
    for (&gid, &ch) in glyphs {
        cmap.pair(gid, ch);
    }
    pdf.cmap(refs.to_unicode, &cmap.finish());
}

fn deflate(data: &[u8]) -> Vec<u8> {
    miniz_oxide::deflate::compress_to_vec_zlib(data, 6)
}
