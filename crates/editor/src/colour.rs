//! The false-colour scale every intensity picture shares (cube-map view,
//! 3D cube), so the same colour means the same candela everywhere.

use egui::{Color32, Ui};

/// Decades below the peak the colour scale spans: stray light a thousand
/// times dimmer than the beam still shows.
pub const DECADES: f64 = 3.0;

/// Position of `v` on the logarithmic colour scale of a map peaking at
/// `peak`, in [0, 1].
pub fn log_scale(v: f64, peak: f64) -> f32 {
    if v <= 0.0 || peak <= 0.0 {
        0.0
    } else {
        ((v / peak).log10() / DECADES + 1.0).clamp(0.0, 1.0) as f32
    }
}

/// A perceptually ordered false colour (black, blue, magenta, orange,
/// yellow, white) for t in [0, 1].
pub fn false_colour(t: f32) -> Color32 {
    const STOPS: [[f32; 3]; 6] = [
        [0.0, 0.0, 0.0],
        [0.1, 0.1, 0.6],
        [0.7, 0.1, 0.6],
        [0.95, 0.4, 0.1],
        [1.0, 0.85, 0.2],
        [1.0, 1.0, 1.0],
    ];
    let x = t.clamp(0.0, 1.0) * (STOPS.len() - 1) as f32;
    let i = (x as usize).min(STOPS.len() - 2);
    let f = x - i as f32;
    let [r, g, b] = [0, 1, 2].map(|k| {
        let v = STOPS[i][k] + f * (STOPS[i + 1][k] - STOPS[i][k]);
        (v * 255.0).round() as u8
    });
    Color32::from_rgb(r, g, b)
}

/// One swatch per decade below the peak, labelled in cd.
pub fn legend_ui(ui: &mut Ui, peak: f64) {
    ui.horizontal(|ui| {
        for k in (0..=DECADES as i32).rev() {
            let v = peak / 10f64.powi(k);
            let (rect, _) = ui.allocate_exact_size(egui::vec2(14.0, 14.0), egui::Sense::hover());
            ui.painter()
                .rect_filled(rect, 2.0, false_colour(log_scale(v, peak)));
            ui.label(format!("{v:.0} cd"));
        }
    });
}
