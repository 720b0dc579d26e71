//! The EN 12464-1 task areas a work plane is judged against: the
//! maintained illuminance its average must reach and the least
//! uniformity, for `lucerna render --task` and the editor's verdict.

use crate::work_plane::IlluminanceFigures;

/// A task area's EN 12464-1 requirement on the work plane.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TaskTarget {
    pub name: &'static str,
    /// Maintained illuminance Em (lx) the average must reach.
    pub e_m_lx: f64,
    /// Least uniformity U0 = Emin / Eavg.
    pub u0: f64,
}

/// EN 12464-1:2011 (Em and U0 unchanged for these in the 2021 edition),
/// as commonly quoted from its tables; reference numbers of 2011:
/// 5.1.1 circulation areas and corridors 100 lx / 0.40; 5.1.2 stairs,
/// escalators 100 lx / 0.40; 5.4.1 store and stock rooms 100 lx / 0.40;
/// 5.4.2 dispatch, packing and handling areas 300 lx / 0.60; 5.26.1
/// filing, copying 300 lx / 0.40; 5.26.2 writing, typing, reading, data
/// processing 500 lx / 0.60; 5.26.3 technical drawing 750 lx / 0.70;
/// 5.26.5 conference and meeting rooms 500 lx / 0.60; 5.26.6 reception
/// desk 300 lx / 0.60; 5.26.7 archives 200 lx / 0.40; 5.36.2 classrooms
/// 300 lx / 0.60. Em is maintained: a room file's `flux_factor` carries
/// the maintenance factor.
pub const TASK_TARGETS: [TaskTarget; 11] = [
    TaskTarget {
        name: "Corridors, circulation areas",
        e_m_lx: 100.0,
        u0: 0.40,
    },
    TaskTarget {
        name: "Stairs, escalators",
        e_m_lx: 100.0,
        u0: 0.40,
    },
    TaskTarget {
        name: "Warehouse: store and stock rooms",
        e_m_lx: 100.0,
        u0: 0.40,
    },
    TaskTarget {
        name: "Warehouse: dispatch, packing, handling",
        e_m_lx: 300.0,
        u0: 0.60,
    },
    TaskTarget {
        name: "Archives",
        e_m_lx: 200.0,
        u0: 0.40,
    },
    TaskTarget {
        name: "Offices: filing, copying",
        e_m_lx: 300.0,
        u0: 0.40,
    },
    TaskTarget {
        name: "Offices: writing, reading, data processing",
        e_m_lx: 500.0,
        u0: 0.60,
    },
    TaskTarget {
        name: "Offices: technical drawing",
        e_m_lx: 750.0,
        u0: 0.70,
    },
    TaskTarget {
        name: "Conference and meeting rooms",
        e_m_lx: 500.0,
        u0: 0.60,
    },
    TaskTarget {
        name: "Reception desk",
        e_m_lx: 300.0,
        u0: 0.60,
    },
    TaskTarget {
        name: "Classrooms",
        e_m_lx: 300.0,
        u0: 0.60,
    },
];

impl TaskTarget {
    /// Whether the work plane meets it: Eavg ≥ Em and U0 ≥ the target's.
    pub fn met_by(&self, figures: &IlluminanceFigures) -> bool {
        figures.e_avg_lx >= self.e_m_lx && figures.u0 >= self.u0
    }

    /// The target a room file's name suggests (office, corridor, meeting).
    pub fn for_room(name: &str) -> usize {
        let name = name.to_lowercase();
        let pick = |needle: &str| TASK_TARGETS.iter().position(|t| t.name.contains(needle));
        let found = if name.contains("corridor") {
            pick("Corridors")
        } else if name.contains("meeting") || name.contains("conference") {
            pick("Conference")
        } else if name.contains("warehouse") || name.contains("store") {
            pick("store and stock")
        } else {
            pick("writing")
        };
        found.unwrap_or(0)
    }

    /// The task whose name contains `words` (case ignored), for a command
    /// line's `--task`.
    pub fn find(words: &str) -> Option<TaskTarget> {
        let words = words.to_lowercase();
        TASK_TARGETS
            .iter()
            .find(|t| t.name.to_lowercase().contains(&words))
            .copied()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn figures(e_avg_lx: f64, u0: f64) -> IlluminanceFigures {
        IlluminanceFigures {
            e_min_lx: u0 * e_avg_lx,
            e_avg_lx,
            e_max_lx: 2.0 * e_avg_lx,
            u0,
            points: 100,
        }
    }

    #[test]
    fn a_target_is_met_by_enough_light_and_uniformity_together() {
        let office = TASK_TARGETS[TaskTarget::for_room("office.toml Office")];
        assert_eq!((office.e_m_lx, office.u0), (500.0, 0.60));
        assert!(office.met_by(&figures(500.0, 0.60)));
        assert!(!office.met_by(&figures(499.0, 0.9)));
        assert!(!office.met_by(&figures(900.0, 0.59)));
        let corridor = TASK_TARGETS[TaskTarget::for_room("corridor.toml")];
        assert_eq!((corridor.e_m_lx, corridor.u0), (100.0, 0.40));
        assert_eq!(
            TASK_TARGETS[TaskTarget::for_room("meeting_room")].name,
            "Conference and meeting rooms"
        );
    }

    #[test]
    fn a_task_is_found_by_a_word_of_its_name() {
        assert_eq!(
            TaskTarget::find("classrooms").map(|t| t.e_m_lx),
            Some(300.0)
        );
        assert_eq!(
            TaskTarget::find("Technical drawing").map(|t| t.u0),
            Some(0.70)
        );
        assert!(TaskTarget::find("spaceship").is_none());
    }
}
