//! The live preview room: a room of `crates/room` lit by the current
//! distribution, updated as the simulation converges and after each edit.

use egui::Ui;

use crate::state::EditorState;

/// The room view's own state (its room, renderer and last picture).
#[derive(Debug, Default)]
pub struct RoomView {}

pub fn room_ui(ui: &mut Ui, _state: &mut EditorState, _room: &mut RoomView) {
    ui.label("The preview room is not built yet.");
}
