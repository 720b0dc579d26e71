//! What is selected: its own module, named by the commands, the document
//! and the modelling edits alike.

/// What is selected in the scene panel.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Selection {
    Emitter(usize),
    Part(usize),
    Material(String),
}
