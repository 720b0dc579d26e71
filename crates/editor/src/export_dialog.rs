//! The export dialog: IES (LM-63-2019 or 2002), EULUMDAT, the map's EXR
//! and PNGs, with the keywords, grid, symmetry and raw or filtered choice;
//! the files are those `lucerna bake` writes for the same settings.

use crate::state::EditorState;

/// The export dialog's own state while it is open.
#[derive(Debug, Default)]
pub struct ExportDialog {
    pub open: bool,
}

/// Draws the dialog as a window when it is open.
pub fn export_dialog_ui(ctx: &egui::Context, _state: &mut EditorState, dialog: &mut ExportDialog) {
    let mut open = dialog.open;
    egui::Window::new("Export").open(&mut open).show(ctx, |ui| {
        ui.label("Export is not built yet.");
    });
    dialog.open = open;
}
