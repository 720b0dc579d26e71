//! The dockable view area (egui_tiles): the 3D view, the profile editor
//! and the photometric views as tabs and splits a user rearranges by
//! dragging (the polar diagram beside the room, say). The layout is kept
//! in the config directory (`layout.json`) between sessions.

use std::path::PathBuf;

use egui::Ui;
use egui_tiles::{Container, Linear, LinearDir, Shares, Tile, TileId, Tiles, Tree};

use crate::design_pane::design_pane_ui;
pub use crate::pane::Pane;
use crate::pane::View;
use crate::profile_pane::{ProfilePane, profile_pane_ui};
use crate::state::EditorState;
use crate::viewport::{Viewport, viewport_ui};
use crate::views::{ViewsState, photometric_view_ui};

/// The tree of panes and where it is kept.
#[derive(Debug)]
pub struct Dock {
    tree: Tree<Pane>,
    /// `layout.json` in the config directory; `None` keeps nothing.
    file: Option<PathBuf>,
    /// The layout as last written, to write only changes.
    written: Option<String>,
}

/// The layout a first session starts with: the 3D view, the profile, the
/// room and the design as tabs on the left, the photometric plots as tabs
/// on the right (the room or the design beside the polar diagram), half
/// each.
fn default_tree() -> Tree<Pane> {
    let mut tiles = Tiles::default();
    let left = vec![
        tiles.insert_pane(Pane::Luminaire),
        tiles.insert_pane(Pane::Profile),
        tiles.insert_pane(Pane::View(View::Room)),
        tiles.insert_pane(Pane::Design),
        tiles.insert_pane(Pane::Tolerance),
    ];
    let left = tiles.insert_tab_tile(left);
    let right: Vec<TileId> = Pane::ALL[2..7]
        .iter()
        .map(|&p| tiles.insert_pane(p))
        .collect();
    let right = tiles.insert_tab_tile(right);
    let mut shares = Shares::default();
    shares.set_share(left, 1.0);
    shares.set_share(right, 1.0);
    let root = tiles.insert_container(Container::Linear(Linear {
        children: vec![left, right],
        dir: LinearDir::Horizontal,
        shares,
    }));
    Tree::new(egui::Id::unique("lucerna dock"), root, tiles)
}

impl Dock {
    /// The layout kept in `file`, else the default one.
    pub fn load(file: Option<PathBuf>) -> Dock {
        let kept = file
            .as_ref()
            .and_then(|f| std::fs::read_to_string(f).ok())
            .and_then(|text| serde_json::from_str::<Tree<Pane>>(&text).ok())
            // A layout that lost a pane (an older version's) is not kept.
            .filter(|tree| Pane::ALL.iter().all(|&p| find(tree, p).is_some()));
        Dock {
            tree: kept.unwrap_or_else(default_tree),
            file,
            written: None,
        }
    }

    /// Back to the default layout.
    pub fn reset(&mut self) {
        self.tree = default_tree();
    }

    /// Brings `pane` to the front of its tabs.
    pub fn show(&mut self, pane: Pane) {
        if let Some(id) = find(&self.tree, pane) {
            self.tree.make_active(|tile_id, _| tile_id == id);
        }
    }

    /// The photometric view in front, if one is visible.
    pub fn front_view(&self) -> Option<View> {
        self.tree
            .active_tiles()
            .into_iter()
            .find_map(|id| match self.tree.tiles.get(id) {
                Some(Tile::Pane(Pane::View(v))) => Some(*v),
                _ => None,
            })
    }

    /// Whether `pane` is drawn this frame (a front tab).
    pub fn is_visible(&self, pane: Pane) -> bool {
        find(&self.tree, pane).is_some_and(|id| self.tree.active_tiles().contains(&id))
    }

    pub fn ui(
        &mut self,
        ui: &mut Ui,
        state: &mut EditorState,
        views: &mut ViewsState,
        viewport: &mut Viewport,
        profile: &mut ProfilePane,
    ) {
        let mut behavior = Behavior {
            state,
            views,
            viewport,
            profile,
        };
        self.tree.ui(&mut behavior, ui);
    }

    /// Writes the layout if it changed since it was last written
    /// (atomically, like every file Lucerna writes).
    pub fn save_if_changed(&mut self) {
        let Some(file) = &self.file else { return };
        let Ok(text) = serde_json::to_string(&self.tree) else {
            return;
        };
        if self.written.as_deref() == Some(&text) {
            return;
        }
        if let Some(dir) = file.parent() {
            let _ = std::fs::create_dir_all(dir);
        }
        if lucerna_scene::io::write_atomically(file, text.as_bytes()).is_ok() {
            self.written = Some(text);
        }
    }
}

fn find(tree: &Tree<Pane>, pane: Pane) -> Option<TileId> {
    tree.tiles
        .iter()
        .find(|(_, tile)| matches!(tile, Tile::Pane(p) if *p == pane))
        .map(|(&id, _)| id)
}

struct Behavior<'a> {
    state: &'a mut EditorState,
    views: &'a mut ViewsState,
    viewport: &'a mut Viewport,
    profile: &'a mut ProfilePane,
}

impl egui_tiles::Behavior<Pane> for Behavior<'_> {
    fn tab_title_for_pane(&mut self, pane: &Pane) -> egui::WidgetText {
        pane.title().into()
    }

    fn pane_ui(
        &mut self,
        ui: &mut Ui,
        _tile_id: TileId,
        pane: &mut Pane,
    ) -> egui_tiles::UiResponse {
        // A margin, so a pane's edge is not the tab bar's.
        egui::Frame::new()
            .inner_margin(egui::Margin::same(4))
            .show(ui, |ui| match *pane {
                Pane::Luminaire => viewport_ui(ui, self.state, self.viewport),
                Pane::Profile => {
                    // The design owns the scene while it runs.
                    let editable = !self.state.design.is_running();
                    ui.add_enabled_ui(editable, |ui| {
                        profile_pane_ui(ui, self.state, self.profile);
                    });
                }
                Pane::View(v) => photometric_view_ui(ui, self.state, self.views, v),
                Pane::Design => design_pane_ui(ui, self.state, self.views),
                Pane::Tolerance => crate::tolerance_pane::tolerance_pane_ui(ui, self.state),
            });
        egui_tiles::UiResponse::None
    }

    fn simplification_options(&self) -> egui_tiles::SimplificationOptions {
        egui_tiles::SimplificationOptions {
            all_panes_must_have_tabs: true,
            ..egui_tiles::SimplificationOptions::default()
        }
    }
}
