//! Studies of the pump's controllers, written on rhonn's public API only (the scenarios,
//! the runner, the controller registry): what the shipped tunings and settings rest on,
//! kept out of the library.
//!
//! - [`tuning`]: the cascade PI's tuning search, the robustness study's plants, and the
//!   loop's margins measured on the simulated pump by sine injection
//!   (`examples/tune_cascade_pi.rs`, `examples/control_robustness.rs`).
//! - [`front`]: IAE against the current's total variation for every setting, and the
//!   front no setting beats on both (`examples/control_front.rs`, `adaptive_sweep.rs`,
//!   `actuator_study.rs`); [`front_plot`] writes it as `front.csv` and `front.svg`.
//!
//! `tests/controllers.rs` reruns the claims they support.

pub mod front;
pub mod front_plot;
pub mod tuning;
