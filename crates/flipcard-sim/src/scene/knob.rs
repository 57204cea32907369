//! Knobs: numbers of a scene the learner may turn while exploring it (issue
//! 24 §1), and the measure plotted against the knob as they turn. A knob
//! names a system scene's parameter (`g`) or start (`initial.theta`), or a
//! rigid body's moment (`inertia[1]`) or start spin (`omega[1]`); it shows
//! its value in its own unit and gives the scene value × `scale`. Stepping
//! stays on the grid `min + k·step` within `[min, max]`, so every value a
//! learner can reach is one `check` has judged by its ends and middle.

use flipcard_text::Text;

use crate::scene::spec::{Measure, Scene, SystemScene};

/// The number of a scene a knob turns.
#[derive(Debug, Clone, PartialEq)]
pub enum Target {
    /// A system scene's parameter, by name.
    Param(String),
    /// A system scene's initial value of the variable at this index, with
    /// the variable's name.
    Initial(usize, String),
    /// A rigid body's principal moment `inertia[i]`.
    Inertia(usize),
    /// A rigid body's initial spin component `omega[i]`.
    Omega(usize),
}

impl Target {
    /// The knob's `name` as a deck writes it.
    pub fn name(&self) -> String {
        match self {
            Target::Param(p) => p.clone(),
            Target::Initial(_, v) => format!("initial.{v}"),
            Target::Inertia(i) => format!("inertia[{i}]"),
            Target::Omega(i) => format!("omega[{i}]"),
        }
    }

    /// The target `name` stands for in a rigid body: `inertia[i]` or
    /// `omega[i]`, i = 0, 1, 2.
    pub fn rigid(name: &str) -> Option<Target> {
        let (field, rest) = name.split_once('[')?;
        let i: usize = rest.strip_suffix(']')?.trim().parse().ok()?;
        if i > 2 {
            return None;
        }
        match field.trim() {
            "inertia" => Some(Target::Inertia(i)),
            "omega" => Some(Target::Omega(i)),
            _ => None,
        }
    }

    /// The target `name` stands for in a system scene: a parameter's name
    /// or `initial.VAR`.
    pub fn system(scene: &SystemScene, name: &str) -> Option<Target> {
        if let Some(var) = name.strip_prefix("initial.") {
            let i = scene.variables.iter().position(|v| v == var)?;
            return Some(Target::Initial(i, var.to_string()));
        }
        scene
            .params
            .iter()
            .any(|(p, _)| p == name)
            .then(|| Target::Param(name.to_string()))
    }
}

/// One knob as the deck declares it.
#[derive(Debug, Clone, PartialEq)]
pub struct Knob {
    pub target: Target,
    /// The range and step in the knob's own unit.
    pub min: f64,
    pub max: f64,
    pub step: f64,
    /// The scene gets the knob's value × `scale` (1 unless a unit is
    /// converted: degrees shown, radians run).
    pub scale: f64,
    /// What the knob turns, in words, in every language.
    pub label: Text,
}

/// How many steps a knob may have: a range of more is a typo.
pub const MAX_STEPS: f64 = 1e6;

impl Knob {
    /// The value one step up (`up`) or down from `value`, on the grid
    /// `min + k·step` or at an end, never outside `[min, max]`. A value off
    /// the grid (the scene's own) moves to the next grid point that way.
    pub fn stepped(&self, value: f64, up: bool) -> f64 {
        let (min, max, step) = (self.min, self.max, self.step);
        if !(min.is_finite() && max.is_finite() && step.is_finite() && step > 0.0 && min < max) {
            return value;
        }
        let value = if value.is_finite() {
            value.clamp(min, max)
        } else {
            min
        };
        let last = ((max - min) / step).floor().min(MAX_STEPS);
        let at = (value - min) / step;
        let near = at.round();
        let on_grid = (at - near).abs() <= 1e-9 * at.abs().max(1.0);
        let k = match (up, on_grid) {
            (true, true) => near + 1.0,
            (false, true) => near - 1.0,
            (true, false) => at.ceil(),
            (false, false) => at.floor(),
        };
        if k < 0.0 {
            min
        } else if k > last {
            max
        } else {
            (min + k * step).clamp(min, max)
        }
    }

    /// The middle of the range on the grid (what `check` samples besides
    /// the ends).
    pub fn middle(&self) -> f64 {
        let k = (((self.max - self.min) / self.step) / 2.0).floor();
        (self.min + k * self.step).clamp(self.min, self.max)
    }
}

/// `v` to 10 significant digits: a knob value as people read it, without
/// the rounding of `min + k·step` or of a unit's conversion
/// (`0.30000000000000004` → 0.3, 29.999999999999996 → 30).
pub fn tidy(v: f64) -> f64 {
    format!("{v:.9e}").parse().unwrap_or(v)
}

/// What a scene offers to explore: its knobs and the measure plotted
/// against the selected one.
#[derive(Debug, Clone, PartialEq)]
pub struct Explore {
    /// The scene's id.
    pub scene: String,
    pub knobs: Vec<Knob>,
    /// `explore = "period(theta)"`: plotted against the knob.
    pub measure: Option<Measure>,
}

/// The scene's own value of `target`, in scene units (`None` when the
/// target is not the scene's).
pub fn rigid_value(scene: &Scene, target: &Target) -> Option<f64> {
    match target {
        Target::Inertia(i) => scene.inertia.get(*i).copied(),
        Target::Omega(i) => scene.omega.get(*i).copied(),
        _ => None,
    }
}

/// As [`rigid_value`] for a system scene.
pub fn system_value(scene: &SystemScene, target: &Target) -> Option<f64> {
    match target {
        Target::Param(p) => scene.params.iter().find(|(n, _)| n == p).map(|(_, v)| *v),
        Target::Initial(i, _) => scene.initial.get(*i).copied(),
        _ => None,
    }
}

/// `scene` with `target` set to `value` (scene units).
pub fn set_rigid(scene: &Scene, target: &Target, value: f64) -> Scene {
    let mut out = scene.clone();
    match target {
        Target::Inertia(i) if *i < 3 => out.inertia[*i] = value,
        Target::Omega(i) if *i < 3 => out.omega[*i] = value,
        _ => {}
    }
    out
}

/// `scene` with `target` set to `value` (scene units).
pub fn set_system(scene: &SystemScene, target: &Target, value: f64) -> SystemScene {
    let mut out = scene.clone();
    match target {
        Target::Param(p) => {
            if let Some(slot) = out.params.iter_mut().find(|(n, _)| n == p) {
                slot.1 = value;
            }
        }
        Target::Initial(i, _) => {
            if let Some(slot) = out.initial.get_mut(*i) {
                *slot = value;
            }
        }
        _ => {}
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn knob(min: f64, max: f64, step: f64) -> Knob {
        Knob {
            target: Target::Param("g".into()),
            min,
            max,
            step,
            scale: 1.0,
            label: Text::default(),
        }
    }

    #[test]
    fn steps_on_the_grid_and_stops_at_the_ends() {
        let k = knob(5.0, 179.0, 5.0);
        assert_eq!(k.stepped(30.0, true), 35.0);
        assert_eq!(k.stepped(30.0, false), 25.0);
        assert_eq!(k.stepped(5.0, false), 5.0);
        assert_eq!(k.stepped(175.0, true), 179.0);
        assert_eq!(k.stepped(179.0, true), 179.0);
        assert_eq!(k.stepped(179.0, false), 175.0);
        // Off the grid: to the next grid point that way.
        assert_eq!(k.stepped(31.0, true), 35.0);
        assert_eq!(k.stepped(31.0, false), 30.0);
        assert_eq!(k.middle(), 90.0);
    }

    // Longer: PROPTEST_CASES=100000 cargo test --lib knob::
    proptest::proptest! {
        #[test]
        fn stepping_stays_on_the_grid_within_the_range(
            min in -1e3f64..1e3,
            span in 1e-3f64..1e3,
            steps in 1u32..400,
            start in 0f64..=1.0,
            presses in proptest::collection::vec(proptest::bool::ANY, 1..60),
        ) {
            let max = min + span;
            let step = span / f64::from(steps) * 1.37;
            let k = knob(min, max, step);
            // From any value in the range (the scene's own may be off the grid).
            let mut v = min + start * span;
            for up in presses {
                let next = k.stepped(v, up);
                proptest::prop_assert!((min..=max).contains(&next), "{next} outside [{min}, {max}]");
                let at = (next - min) / step;
                let on_grid = (at - at.round()).abs() <= 1e-9 * at.abs().max(1.0);
                proptest::prop_assert!(
                    on_grid || next == min || next == max,
                    "{next} is neither min + k·{step} nor an end"
                );
                // It moves the way pressed, unless at that end.
                if up {
                    proptest::prop_assert!(next > v || next == max, "{v} → {next} up");
                } else {
                    proptest::prop_assert!(next < v || next == min, "{v} → {next} down");
                }
                v = next;
            }
        }
    }

    #[test]
    fn names_read_back() {
        assert_eq!(Target::rigid("inertia[1]"), Some(Target::Inertia(1)));
        assert_eq!(Target::rigid("omega[2]"), Some(Target::Omega(2)));
        assert_eq!(Target::rigid("omega[3]"), None);
        assert_eq!(Target::rigid("mass[0]"), None);
        assert_eq!(Target::Inertia(1).name(), "inertia[1]");
        assert_eq!(Target::Initial(0, "theta".into()).name(), "initial.theta");
    }
}
