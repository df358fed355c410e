//! The ROS 2 node over DDS: one participant, a best-effort `LaserScan` subscription (it
//! matches reliable and best-effort publishers), reliable publishers of the outputs, and a
//! loop that extracts every scan as it arrives until told to stop.

use std::net::IpAddr;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use ros2_client::dds::rustdds::DomainParticipantBuilder;
use ros2_client::dds::rustdds::mio1::{Events, Interest, Poll, Token};
use ros2_client::names::NameError;
use ros2_client::qos::{Durability, History, Reliability, WhenFull};
use ros2_client::{
    Context, MessageTypeName, Name, Node, NodeName, NodeOptions, Publisher, QosProfile,
    Subscription,
};
use serde::Serialize;
use tracing::{debug, info, warn};

use crate::msg::{self, LaserScan, LineSegmentList, Marker, MarkerArray};
use crate::process::{Counts, Outputs, Processed, Processor};

/// Where the node lives on the ROS 2 graph and what it publishes where.
#[derive(Debug, Clone, PartialEq)]
pub struct NodeConfig {
    /// Node name.
    pub node_name: String,
    /// Node namespace (relative topic names are resolved in it).
    pub namespace: String,
    /// `sensor_msgs/msg/LaserScan` input.
    pub scan_topic: String,
    /// `LineSegmentList` output.
    pub lines_topic: String,
    /// `visualization_msgs/msg/Marker` output.
    pub markers_topic: String,
    /// `visualization_msgs/msg/MarkerArray` of the sector objects, when wanted.
    pub sectors_topic: Option<String>,
    /// Package of the `LineSegmentList` type.
    pub line_package: String,
    /// Depth of the scan subscription's history (scans kept while the node is busy).
    pub scan_depth: usize,
    /// DDS domain (`ROS_DOMAIN_ID`).
    pub domain_id: u16,
    /// Only these local addresses take part (e.g. `127.0.0.1`: this host only).
    pub only_networks: Option<Vec<IpAddr>>,
}

impl Default for NodeConfig {
    fn default() -> Self {
        Self {
            node_name: "laserlines".to_owned(),
            namespace: "/".to_owned(),
            scan_topic: "/scan".to_owned(),
            lines_topic: "/line_segments".to_owned(),
            markers_topic: "/line_markers".to_owned(),
            sectors_topic: None,
            line_package: msg::LINE_PACKAGE.to_owned(),
            scan_depth: 5,
            domain_id: 0,
            only_networks: None,
        }
    }
}

/// An error setting up the node.
#[derive(Debug, thiserror::Error)]
pub enum NodeError {
    /// A node or topic name ROS 2 does not accept.
    #[error("bad ROS 2 name {name:?}: {reason}")]
    Name {
        /// the name
        name: String,
        /// why
        reason: String,
    },
    /// DDS could not create a participant, topic, reader or writer.
    #[error("cannot create the DDS {what}: {reason}")]
    Create {
        /// what was being created
        what: String,
        /// why
        reason: String,
    },
    /// The poll loop failed.
    #[error("waiting for scans failed: {0}")]
    Poll(#[from] std::io::Error),
}

fn create_err(what: &str, e: impl std::fmt::Debug) -> NodeError {
    NodeError::Create {
        what: what.to_owned(),
        reason: format!("{e:?}"),
    }
}

/// The sensor data profile of `rclcpp::SensorDataQoS`: best effort, volatile, keep last
/// `depth`. A best-effort reader matches reliable and best-effort writers alike.
#[must_use]
pub fn scan_qos(depth: usize) -> QosProfile {
    QosProfile::subscription_default()
        .reliability(Reliability::BestEffort)
        .durability(Durability::Volatile)
        .history(History::KeepLast {
            depth: depth.max(1),
        })
}

/// The outputs' profile, ROS 2's default: reliable, volatile, keep last 10; a full send
/// window waits up to 100 ms for acknowledgements, then the message is counted as not
/// published.
#[must_use]
pub fn output_qos() -> QosProfile {
    QosProfile::publisher_default()
        .reliability(Reliability::Reliable {
            when_full: WhenFull::Wait(Duration::from_millis(100)),
        })
        .durability(Durability::Volatile)
        .history(History::KeepLast { depth: 10 })
}

/// When the loop stops by itself.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Limits {
    /// After this many scans seen.
    pub scans: Option<u64>,
    /// After this long.
    pub duration: Option<Duration>,
    /// Log the counts this often (none: only at the end).
    pub status_every: Option<Duration>,
}

/// The running node: DDS entities and the processor.
pub struct LineNode {
    // Field order is drop order: entities before the node, the node before the context.
    scans: Subscription<LaserScan>,
    lines: Publisher<LineSegmentList>,
    markers: Publisher<Marker>,
    sectors: Option<Publisher<MarkerArray>>,
    node: Node,
    _context: Context,
    processor: Processor,
}

fn parse_name(name: &str) -> Result<Name, NodeError> {
    Name::parse(name).map_err(|e| NodeError::Name {
        name: name.to_owned(),
        reason: name_problem(name, &e),
    })
}

/// The characters a ROS 2 name is made of, in words.
const NAME_CHARS: &str = "letters, digits and underscores, parts separated by slashes, a \
                          node name and each part from a letter or an underscore";

/// What is wrong with `name`, in words: the first character the ROS 2 naming rules do not
/// allow where it stands, as found here (the DDS library names some as `?`), else the
/// library's `e`.
fn name_problem(name: &str, e: &NameError) -> String {
    if let Some(c) = name
        .chars()
        .find(|c| !(c.is_ascii_alphanumeric() || *c == '_' || *c == '/'))
    {
        return match c {
            '~' | '{' | '}' => format!(
                "{c:?} is not allowed: the private namespace (~) and substitutions ({{node}}) \
                 are not resolved here, give the full name ({NAME_CHARS})"
            ),
            _ => format!("{c:?} is not allowed ({NAME_CHARS})"),
        };
    }
    if name.contains("__") {
        return format!("two underscores in a row are not allowed ({NAME_CHARS})");
    }
    if let Some(part) = name
        .split('/')
        .find(|p| p.starts_with(|c: char| c.is_ascii_digit()))
    {
        return format!("the part {part:?} starts with a digit ({NAME_CHARS})");
    }
    match e {
        NameError::Empty => "it is empty".to_owned(),
        NameError::BadChar(c) => format!("{c:?} is not allowed ({NAME_CHARS})"),
        NameError::BadSlash(ns, n) => {
            format!("a slash out of place (namespace {ns:?}, name {n:?})")
        }
    }
}

fn publisher<M: Serialize>(
    node: &mut Node,
    topic: &str,
    kind: MessageTypeName,
) -> Result<Publisher<M>, NodeError> {
    let qos = output_qos();
    let t = node
        .create_topic(&parse_name(topic)?, kind, &qos)
        .map_err(|e| create_err(&format!("topic {topic}"), e))?;
    node.create_publisher(&t, Some(qos))
        .map_err(|e| create_err(&format!("publisher of {topic}"), e))
}

impl LineNode {
    /// Joins the DDS domain and creates the subscription and publishers.
    ///
    /// # Errors
    /// A [`NodeError`] for a bad name or when DDS cannot create an entity (e.g. no network
    /// interface matches `only_networks`).
    pub fn new(config: &NodeConfig, processor: Processor) -> Result<Self, NodeError> {
        let mut builder = DomainParticipantBuilder::new(config.domain_id);
        if let Some(nets) = &config.only_networks {
            builder = builder.with_only_networks(nets.iter().copied());
        }
        let participant = builder.build().map_err(|e| create_err("participant", e))?;
        let context = Context::from_domain_participant(participant)
            .map_err(|e| create_err("ROS 2 context", e))?;
        let node_name = NodeName::new(&config.namespace, &config.node_name).map_err(|e| {
            let name = format!(
                "{}/{}",
                config.namespace.trim_end_matches('/'),
                config.node_name
            );
            let reason = name_problem(&name, &e);
            NodeError::Name { name, reason }
        })?;
        let options = NodeOptions::new()
            .enable_rosout(false)
            .start_parameter_services(false);
        let mut node = context
            .new_node(node_name, options)
            .map_err(|e| create_err("node", e))?;
        let qos = scan_qos(config.scan_depth);
        let topic = node
            .create_topic(
                &parse_name(&config.scan_topic)?,
                msg::laser_scan_type(),
                &qos,
            )
            .map_err(|e| create_err(&format!("topic {}", config.scan_topic), e))?;
        let scans = node
            .create_subscription(&topic, Some(qos))
            .map_err(|e| create_err(&format!("subscription of {}", config.scan_topic), e))?;
        let lines = publisher(
            &mut node,
            &config.lines_topic,
            msg::line_segment_list_type(&config.line_package),
        )?;
        let markers = publisher(&mut node, &config.markers_topic, msg::marker_type())?;
        let sectors = match &config.sectors_topic {
            Some(t) => Some(publisher(&mut node, t, msg::marker_array_type())?),
            None => None,
        };
        Ok(Self {
            scans,
            lines,
            markers,
            sectors,
            node,
            _context: context,
            processor,
        })
    }

    /// The node's fully qualified name.
    #[must_use]
    pub fn name(&self) -> String {
        self.node.fully_qualified_name()
    }

    /// Extracts and publishes every scan as it arrives until `stop` is set or a limit is
    /// reached; returns the counts.
    ///
    /// # Errors
    /// [`NodeError::Poll`] when the operating system's poll fails.
    pub fn spin(&mut self, stop: &AtomicBool, limits: &Limits) -> Result<Counts, NodeError> {
        let mut poll = Poll::new()?;
        poll.registry()
            .register(&mut self.scans, Token(0), Interest::READABLE)?;
        let mut events = Events::with_capacity(4);
        let start = Instant::now();
        let mut last_status = start;
        let mut out = Outputs::default();
        loop {
            if stop.load(Ordering::Relaxed) {
                info!("stopping (signal)");
                break;
            }
            if limits.duration.is_some_and(|d| start.elapsed() >= d) {
                info!("stopping (duration reached)");
                break;
            }
            if limits
                .scans
                .is_some_and(|n| self.processor.counts().seen >= n)
            {
                info!("stopping (scan count reached)");
                break;
            }
            if let Some(every) = limits.status_every
                && last_status.elapsed() >= every
            {
                info!("{}", self.processor.counts());
                last_status = Instant::now();
            }
            // Edge-triggered: drain what has arrived; the timeout bounds how late a stop
            // is seen.
            match poll.poll(&mut events, Some(Duration::from_millis(100))) {
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                r => r?,
            }
            self.drain(&mut out, limits.scans);
        }
        poll.registry().deregister(&mut self.scans)?;
        Ok(*self.processor.counts())
    }

    /// Takes and handles every scan waiting (up to the scan limit).
    fn drain(&mut self, out: &mut Outputs, max_scans: Option<u64>) {
        while max_scans.is_none_or(|n| self.processor.counts().seen < n) {
            match self.scans.take() {
                Ok(Some((scan, _info))) => self.handle(&scan, out),
                Ok(None) => break,
                Err(e) => {
                    self.processor.count_undecodable();
                    let n = self.processor.counts().skipped_undecodable;
                    if worth_warning(n) {
                        warn!("a message on the scan topic is not a LaserScan ({n} so far): {e:?}");
                    }
                }
            }
        }
    }

    fn handle(&mut self, scan: &LaserScan, out: &mut Outputs) {
        match self.processor.process(scan, out) {
            Processed::Skipped(e) => {
                let n = self.processor.counts().skipped_geometry;
                if worth_warning(n) {
                    warn!(
                        "scan {} skipped, nothing published: {e} ({n} skipped so far)",
                        self.processor.counts().seen
                    );
                }
            }
            Processed::Extracted {
                lines,
                extract_us,
                ranges,
            } => {
                let c = self.processor.counts();
                if ranges.total() > 0 && c.scans_with_bad_ranges == 1 {
                    warn!(
                        "scan {}: {} of {} ranges are no measurement ({ranges}), not used; \
                         further ones are counted in the status lines",
                        c.seen,
                        ranges.total(),
                        scan.ranges.len()
                    );
                }
                debug!("scan {}: {lines} lines in {extract_us:.1} us", c.seen);
                self.publish(out);
            }
        }
    }

    fn publish(&mut self, out: &Outputs) {
        let mut failed = self.lines.publish(out.lines.clone()).is_err();
        failed |= self.markers.publish(out.marker.clone()).is_err();
        if let (Some(p), Some(m)) = (&self.sectors, &out.sectors) {
            failed |= p.publish(m.clone()).is_err();
        }
        if failed {
            self.processor.count_publish_failed();
            let n = self.processor.counts().publish_failed;
            if worth_warning(n) {
                warn!("outputs of a scan not published: send window full ({n} so far)");
            }
        }
    }
}

/// Warn on the first ten occurrences, then on every hundredth.
fn worth_warning(n: u64) -> bool {
    n <= 10 || n.is_multiple_of(100)
}

#[cfg(test)]
mod tests {
    use super::parse_name;

    fn problem(name: &str) -> String {
        parse_name(name).err().unwrap().to_string()
    }

    #[test]
    fn bad_names_are_said_in_words() {
        assert!(parse_name("/scan").is_ok());
        assert!(parse_name("/robot_1/scan").is_ok());
        assert!(
            problem("/bad topic").starts_with("bad ROS 2 name \"/bad topic\": ' ' is not allowed"),
            "{}",
            problem("/bad topic")
        );
        assert_eq!(problem(""), "bad ROS 2 name \"\": it is empty");
        // The character at fault is named, not the library's `?`.
        for (name, says) in [
            ("~/scan", "'~' is not allowed: the private namespace"),
            ("{node}/scan", "'{' is not allowed: the private namespace"),
            ("/scan__x", "two underscores in a row are not allowed"),
            ("/scan-x", "'-' is not allowed (letters"),
            ("/robot/1scan", "the part \"1scan\" starts with a digit"),
        ] {
            let p = problem(name);
            assert!(p.contains(says), "{name}: {p}");
        }
        let slash = problem("/a//b");
        assert!(slash.contains("a slash out of place"), "{slash}");
    }
}
