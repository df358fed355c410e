//! A ROS 2 node with no ROS install: it subscribes to `sensor_msgs/msg/LaserScan`, extracts
//! lines with any extractor of [`laserlines::registry`] and publishes them as
//! laser_line_extraction's `LineSegmentList` (same type name and fields, so its subscribers
//! work unchanged) and as an RViz `LINE_LIST` marker; with `--sectors`, the paper's three
//! sector objects as markers. It speaks DDS through `ros2-client` (pure Rust over RustDDS).
//!
//! | module | what |
//! |---|---|
//! | [`msg`] | the messages, field for field as their `.msg` files |
//! | [`convert`] | `LaserScan` to [`laserlines::Scan`], lines to `LineSegmentList` and a marker |
//! | [`sectors`] | the sector objects as markers |
//! | [`process`] | one scan through the extractor into the outputs, and the counts |
//! | [`node`] | the DDS participant, subscription, publishers and the loop |
//! | [`wire`] | messages as DDS carries them (encapsulation header and CDR) |
//! | [`args`] | the command line of `laserlines-ros2` |

pub mod args;
pub mod convert;
pub mod msg;
pub mod node;
pub mod process;
pub mod sectors;
pub mod wire;
