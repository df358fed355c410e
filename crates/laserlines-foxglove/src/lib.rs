//! # laserlines-foxglove
//!
//! MCAP and Foxglove for laserlines.
