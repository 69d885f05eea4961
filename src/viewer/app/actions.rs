//! The viewer's key actions ([`Action`]) applied to what is shown.

use super::App;
use crate::viewer::controls::{Action, cycle_index};
use winit::event_loop::ActiveEventLoop;

impl App {
    pub(super) fn handle(&mut self, event_loop: &ActiveEventLoop, action: Action) {
        if self.editing.is_some() {
            match action {
                Action::CycleFabric(_)
                | Action::SelectFabric(_)
                | Action::CycleEvaluator(_)
                | Action::Finer(_) => {
                    println!(
                        "clothbake view: while editing, the panel chooses what shades the drape"
                    );
                    return;
                }
                Action::ToggleEnvironment if self.setup.environment.is_some() => {
                    self.environment_on = !self.environment_on;
                    return;
                }
                _ => {}
            }
        }
        let (index, slot) = (self.current, self.evaluator);
        let shown = self.evaluators[slot].clone();
        match action {
            Action::Quit => event_loop.exit(),
            Action::CycleFabric(step) => {
                let next = cycle_index(index, step, self.setup.fabrics.len());
                self.show_or_report(next, slot, shown);
            }
            Action::SelectFabric(next) => {
                if next < self.setup.fabrics.len() {
                    self.show_or_report(next, slot, shown);
                }
            }
            Action::RotateLight {
                azimuth_deg,
                elevation_deg,
            } => {
                if self.light.has_light() {
                    self.light.rotate(azimuth_deg, elevation_deg);
                } else {
                    eprintln!("clothbake view: the scene has no directional light to move");
                }
            }
            Action::ToggleLightSpin => self.light.spinning = !self.light.spinning,
            Action::CycleEvaluator(step) => {
                let next = cycle_index(slot, step, self.evaluators.len());
                self.show_or_report(index, next, self.evaluators[next].clone());
            }
            Action::Finer(finer) => match shown.step(finer) {
                Some(next) => self.show_or_report(index, slot, next),
                None => println!(
                    "clothbake view: {} has no {} setting",
                    shown.spelling(),
                    if finer { "finer" } else { "coarser" }
                ),
            },
            Action::ToggleEnvironment => {
                if self.setup.environment.is_none() {
                    println!("clothbake view: the scene has no environment light (--env)");
                } else {
                    self.environment_on = !self.environment_on;
                    println!(
                        "clothbake view: environment light {}",
                        if self.environment_on { "on" } else { "off" }
                    );
                    self.show_or_report(index, slot, shown);
                }
            }
            Action::RotateEnvironment(degrees) => {
                self.environment_rotation_deg = (self.environment_rotation_deg + degrees) % 360.0;
                println!(
                    "clothbake view: environment turned to {:.0}°",
                    self.environment_rotation_deg
                );
            }
            Action::ResetView => {
                self.orbit.reset();
                self.light.reset();
            }
        }
    }
}
