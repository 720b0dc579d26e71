//! The window: the panels around the views, one frame at a time.

use crate::files_bar::files_bar_ui;
use crate::scene_panel::scene_panel_ui;
use crate::simulation_panel::simulation_panel_ui;
use crate::state::EditorState;
use crate::views::{CubeTexture, views_ui};

/// The editor: its state and the textures only drawing needs.
#[derive(Debug)]
pub struct EditorApp {
    pub state: EditorState,
    cube: CubeTexture,
}

impl EditorApp {
    pub fn new(state: EditorState) -> Self {
        EditorApp {
            state,
            cube: CubeTexture::default(),
        }
    }

    /// One frame of the whole editor; the eframe app and the tests both
    /// drive this.
    pub fn ui(&mut self, ui: &mut egui::Ui) {
        let ctx = ui.ctx().clone();
        self.state.begin_frame(&ctx);
        let before = self.state.scene.clone();
        egui::Panel::top("files").show(ui, |ui| files_bar_ui(ui, &mut self.state));
        egui::Panel::left("scene")
            .resizable(true)
            .default_size(300.0)
            .show(ui, |ui| {
                egui::ScrollArea::vertical().show(ui, |ui| scene_panel_ui(ui, &mut self.state));
            });
        egui::Panel::right("simulation")
            .resizable(true)
            .default_size(270.0)
            .show(ui, |ui| {
                egui::ScrollArea::vertical()
                    .show(ui, |ui| simulation_panel_ui(ui, &mut self.state));
            });
        egui::CentralPanel::default().show(ui, |ui| views_ui(ui, &mut self.state, &mut self.cube));
        self.state.end_frame(&ctx, before);
    }
}

impl eframe::App for EditorApp {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        EditorApp::ui(self, ui);
    }
}
