//! The views and panes the editor can show: the one list of them that
//! the state, the dock, the menus and the command line share.

use serde::{Deserialize, Serialize};

/// Which view the central panel shows.
/// Serialised by name, so a dock layout file outlives the enum's order;
/// `lucerna-editor --view` names them too.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, clap::ValueEnum)]
pub enum View {
    #[default]
    Polar,
    /// I(γ) per C-plane, linear or log.
    Cartesian,
    /// The C-γ map with lines of equal intensity.
    Isocandela,
    #[value(name = "cube")]
    CubeMap,
    /// Every figure with its noise, copyable as text.
    Figures,
    /// The preview room lit by the current distribution.
    Room,
}

/// One pane of the dock.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Pane {
    /// The 3D view of the luminaire.
    Luminaire,
    /// The selected part's profile, large.
    Profile,
    /// A photometric view.
    View(View),
    /// Design toward a target: its setup, run and merit plot.
    Design,
    /// Tolerance analysis: the yield of the built luminaire.
    Tolerance,
}

impl Pane {
    /// Every pane, in menu order.
    pub const ALL: [Pane; 10] = [
        Pane::Luminaire,
        Pane::Profile,
        Pane::View(View::Polar),
        Pane::View(View::Cartesian),
        Pane::View(View::Isocandela),
        Pane::View(View::CubeMap),
        Pane::View(View::Figures),
        Pane::View(View::Room),
        Pane::Design,
        Pane::Tolerance,
    ];

    /// Its tab's title (also the tab button's accessible name).
    pub fn title(self) -> &'static str {
        match self {
            Pane::Luminaire => "3D view",
            Pane::Profile => "Profile",
            Pane::View(View::Polar) => "Polar",
            Pane::View(View::Cartesian) => "Cartesian",
            Pane::View(View::Isocandela) => "Isocandela",
            Pane::View(View::CubeMap) => "Cube map",
            Pane::View(View::Figures) => "Figures",
            Pane::View(View::Room) => "Room",
            Pane::Design => "Design",
            Pane::Tolerance => "Tolerance",
        }
    }

    pub fn of_view(view: View) -> Pane {
        Pane::View(view)
    }
}
