//! The photometric views, one file each, redrawn from each snapshot, each
//! a pane of the dock. The polar, cartesian and isocandela views share the
//! options row: unit, raw or exported table, an extra C-plane, and a
//! reference to compare with.

mod cartesian;
mod cube_map;
mod figures;
mod isocandela;
mod polar;

use std::path::PathBuf;
use std::sync::Arc;

use egui::Ui;
use lucerna_photometry::CandelaTable;
use lucerna_simulation::Snapshot;

pub use cube_map::CubeTexture;

use crate::reference::Reference;
use crate::room_view::{RoomView, room_ui};
use crate::state::{EditorState, View};
use crate::widgets::labelled;

pub use crate::intensity_unit::IntensityUnit;

/// What only drawing the views needs: their options, the reference, and
/// textures and caches rebuilt per snapshot.
#[derive(Default)]
pub struct ViewsState {
    pub cube: CubeTexture,
    pub room: RoomView,
    pub unit: IntensityUnit,
    /// Show the unfiltered table (when a filter is on).
    pub raw: bool,
    /// A C-plane drawn besides C0-C180 and C90-C270 (degrees).
    pub extra_plane: Option<f64>,
    pub cartesian: cartesian::CartesianOptions,
    pub isocandela: isocandela::IsocandelaCache,
    pub reference: Option<Reference>,
    pub reference_path: String,
    pub reference_error: Option<String>,
    /// The RMS difference (cd) of a table from the reference's, kept
    /// while both stay the same: ~50 000 lookups each, not every frame.
    rms: Option<(Arc<CandelaTable>, Arc<CandelaTable>, f64)>,
}

impl std::fmt::Debug for ViewsState {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ViewsState")
            .field("unit", &self.unit)
            .field("raw", &self.raw)
            .field("extra_plane", &self.extra_plane)
            .field("reference", &self.reference.as_ref().map(|r| &r.name))
            .finish_non_exhaustive()
    }
}

/// The tables a plot draws, scaled to the chosen unit.
pub struct PlotTables<'a> {
    pub current: &'a CandelaTable,
    pub current_factor: f64,
    pub reference: Option<(&'a Reference, f64)>,
    pub extra_plane: Option<f64>,
    pub unit: IntensityUnit,
}

impl ViewsState {
    /// The table shown: exported, or raw when asked and there is one.
    fn shown_table<'s>(&self, snapshot: &'s Snapshot) -> &'s Arc<CandelaTable> {
        if self.raw {
            &snapshot.raw_table
        } else {
            &snapshot.table
        }
    }

    fn plot_tables<'a>(&'a self, snapshot: &'a Snapshot) -> PlotTables<'a> {
        let current = self.shown_table(snapshot);
        let current_factor = self.unit.factor(snapshot.map.emitter_flux_lm);
        PlotTables {
            current,
            current_factor,
            reference: self
                .reference
                .as_ref()
                .map(|r| (r, r.factor(self.unit, current, current_factor))),
            extra_plane: self.extra_plane,
            unit: self.unit,
        }
    }
}

/// One photometric view, as its pane of the dock draws it.
pub fn photometric_view_ui(
    ui: &mut Ui,
    state: &mut EditorState,
    views: &mut ViewsState,
    view: View,
) {
    // The view in front (a benchmark and the room preview ask).
    state.view = view;
    if view == View::Room {
        room_ui(ui, state, &mut views.room);
        return;
    }
    let Some(snapshot) = state.run.snapshot.clone() else {
        ui.label("No light distribution yet.");
        return;
    };
    if matches!(view, View::Polar | View::Cartesian | View::Isocandela) {
        options_ui(ui, &snapshot, views);
    }
    match view {
        View::Polar => polar::polar_ui(ui, &views.plot_tables(&snapshot), &snapshot),
        View::Cartesian => {
            let options = views.cartesian;
            let tables = views.plot_tables(&snapshot);
            let mut changed = options;
            cartesian::cartesian_ui(ui, &tables, &mut changed);
            views.cartesian = changed;
        }
        View::Isocandela => {
            let table = views.shown_table(&snapshot).clone();
            let factor = views.unit.factor(snapshot.map.emitter_flux_lm);
            let unit = views.unit;
            isocandela::isocandela_ui(ui, &table, factor, unit, &mut views.isocandela);
        }
        View::CubeMap => cube_map::cube_map_ui(ui, &snapshot, &mut views.cube),
        View::Figures => figures::figures_ui(ui, &snapshot),
        View::Room => {}
    }
}

/// Unit, raw or exported, extra plane, reference.
fn options_ui(ui: &mut Ui, snapshot: &Arc<Snapshot>, views: &mut ViewsState) {
    ui.horizontal_wrapped(|ui| {
        labelled(ui, "Unit", |ui| {
            egui::ComboBox::from_id_salt("intensity unit")
                .selected_text(views.unit.label())
                .show_ui(ui, |ui| {
                    for u in [IntensityUnit::Candela, IntensityUnit::CandelaPerKilolumen] {
                        ui.selectable_value(&mut views.unit, u, u.label());
                    }
                })
                .response
        });
        let filtered = !Arc::ptr_eq(&snapshot.table, &snapshot.raw_table);
        ui.add_enabled_ui(filtered, |ui| {
            ui.checkbox(&mut views.raw, "Raw (unfiltered)")
                .on_disabled_hover_text("The filter is off: the table is the raw one");
        });
        let mut extra = views.extra_plane.is_some();
        ui.checkbox(&mut extra, "Extra C-plane");
        match (extra, views.extra_plane) {
            (true, None) => views.extra_plane = Some(45.0),
            (false, Some(_)) => views.extra_plane = None,
            _ => {}
        }
        if let Some(c) = &mut views.extra_plane {
            labelled(ui, "C-plane", |ui| {
                ui.add(
                    egui::DragValue::new(c)
                        .range(0.0..=179.9)
                        .speed(0.5)
                        .suffix("°"),
                )
            });
        }
    });
    reference_ui(ui, snapshot, views);
}

fn reference_ui(ui: &mut Ui, snapshot: &Arc<Snapshot>, views: &mut ViewsState) {
    ui.horizontal_wrapped(|ui| {
        labelled(ui, "Reference file", |ui| {
            ui.add(egui::TextEdit::singleline(&mut views.reference_path).desired_width(180.0))
        });
        if ui.button("Load reference").clicked() {
            let path = PathBuf::from(views.reference_path.trim());
            match Reference::load(&path) {
                Ok(r) => {
                    views.reference = Some(r);
                    views.reference_error = None;
                }
                Err(e) => views.reference_error = Some(crate::error_text::error_chain(&e)),
            }
        }
        if ui
            .button("Pin as reference")
            .on_hover_text("Keep this result to compare the next edits with (A/B)")
            .clicked()
        {
            views.reference = Some(Reference::pinned(snapshot));
            views.reference_error = None;
        }
        if views.reference.is_some() && ui.button("Clear reference").clicked() {
            views.reference = None;
        }
    });
    if let Some(e) = &views.reference_error {
        ui.colored_label(ui.visuals().error_fg_color, e);
    }
    if let Some(r) = &views.reference {
        // In candela: the design and the reference as they would light a
        // room, whatever unit the plot uses.
        let current = views.shown_table(snapshot).clone();
        let rms = match &views.rms {
            Some((a, b, rms)) if Arc::ptr_eq(a, &current) && Arc::ptr_eq(b, &r.table) => *rms,
            _ => {
                let rms = current.rms_difference_cd(&r.table);
                views.rms = Some((current.clone(), r.table.clone(), rms));
                rms
            }
        };
        let peak = current.peak().0.max(r.table.peak().0);
        ui.label(format!(
            "Reference {}: RMS difference {rms:.1} cd ({:.1} % of the peak)",
            r.name,
            if peak > 0.0 { 100.0 * rms / peak } else { 0.0 }
        ));
    }
}
