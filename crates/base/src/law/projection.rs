//! Projection onto a ball: after each step a weight vector outside the ball of radius
//! `r` around `c` is put back on its surface along the ray from `c` (Ioannou & Sun 1996,
//! section 4.10.3). The adaptive controller keeps its input-gain weights in a ball
//! around their identified values this way, so the identified gain never reaches zero.

pub use rhonn_core::law::project;
