//! The photometric views beside the 3D view, one file each, redrawn from
//! each snapshot; the tab row picks one.

mod cube_map;
mod polar;

use egui::Ui;

pub use cube_map::CubeTexture;

use crate::room_view::{RoomView, room_ui};
use crate::state::{EditorState, View};

/// What only drawing the views needs (textures, the room's renderer).
#[derive(Debug, Default)]
pub struct ViewsState {
    pub cube: CubeTexture,
    pub room: RoomView,
}

pub fn views_ui(ui: &mut Ui, state: &mut EditorState, views: &mut ViewsState) {
    ui.horizontal_wrapped(|ui| {
        for (view, label) in [
            (View::Polar, "Polar diagram"),
            (View::CubeMap, "Cube map"),
            (View::Room, "Room"),
        ] {
            ui.selectable_value(&mut state.view, view, label);
        }
    });
    ui.separator();
    if state.view == View::Room {
        room_ui(ui, state, &mut views.room);
        return;
    }
    let Some(snapshot) = state.snapshot.clone() else {
        ui.label("No light distribution yet.");
        return;
    };
    match state.view {
        View::Polar => polar::polar_ui(ui, &snapshot.table),
        View::CubeMap => cube_map::cube_map_ui(ui, &snapshot, &mut views.cube),
        View::Room => {}
    }
}
