//! When a run is at rest: every grain has appeared and none has been faster than a speed for a
//! number of steps in a row (`run --until-rest`). Written once for the CLI, the viewer, the
//! tests, the measures and `bench peers`, whose other engines report their own fastest grain.

use super::World;

/// The rest criterion: every grain in and none faster than `speed` for `steps` steps in a row.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rest {
    pub speed: f64,
    pub steps: u32,
}

impl Default for Rest {
    /// `run --until-rest`'s: 0.05 units/s (5% of a falling grain's terminal speed under the
    /// paper's damping) for 100 steps.
    fn default() -> Self {
        Rest {
            speed: 0.05,
            steps: 100,
        }
    }
}

/// The steps in a row a run has met its [`Rest`] criterion.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RestCounter {
    calm: u32,
}

impl RestCounter {
    /// After a step of any engine: whether every grain is in (`all_in`) and the fastest is
    /// slower than `rest.speed`; then whether that has held for `rest.steps` steps.
    pub fn update(&mut self, rest: &Rest, all_in: bool, fastest: f64) -> bool {
        self.calm = if all_in && fastest < rest.speed {
            self.calm.saturating_add(1)
        } else {
            0
        };
        self.at_rest(rest)
    }

    /// [`RestCounter::update`] after a step of `world`.
    pub fn after_step(&mut self, rest: &Rest, world: &World) -> bool {
        self.update(rest, world.all_spawned(), world.max_speed())
    }

    /// Whether the criterion has held for `rest.steps` steps in a row.
    pub fn at_rest(&self, rest: &Rest) -> bool {
        self.calm >= rest.steps
    }

    /// The steps in a row it has held.
    pub fn calm(&self) -> u32 {
        self.calm
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fast step or a grain still to come starts the count again; `steps` calm steps in a
    /// row, and only they, are rest.
    #[test]
    fn rest_needs_its_steps_in_a_row_with_every_grain_in() {
        let rest = Rest {
            speed: 0.05,
            steps: 3,
        };
        let mut c = RestCounter::default();
        assert!(!c.update(&rest, true, 0.01));
        assert!(!c.update(&rest, true, 0.01));
        assert!(!c.update(&rest, true, 0.05), "0.05 is not below 0.05");
        assert_eq!(c.calm(), 0);
        assert!(!c.update(&rest, false, 0.0), "a grain still to come");
        assert!(!c.update(&rest, true, 0.0));
        assert!(!c.update(&rest, true, 0.0));
        assert!(c.update(&rest, true, 0.0));
        assert!(c.at_rest(&rest));
    }
}
