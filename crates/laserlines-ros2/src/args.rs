//! The command line of `laserlines-ros2`: the extractor as the `laserlines` CLI chooses it
//! (`--algorithm`, `--params FILE.toml`, `--preset NAME`), the topics, the frame, the DDS
//! domain and network.

use std::net::{IpAddr, Ipv4Addr};
use std::path::PathBuf;
use std::time::Duration;

use anyhow::{Context as _, Result, bail};
use clap::Parser;
use laserlines::registry::BoxedExtractor;
use laserlines_io::params::ParamsFile;

use crate::msg::LINE_PACKAGE;
use crate::node::{Limits, NodeConfig};

/// A ROS 2 node that extracts line segments from laser scans: `sensor_msgs/msg/LaserScan`
/// in, laser_line_extraction's `LineSegmentList` and an RViz marker out. No ROS install
/// needed.
#[derive(Debug, Clone, Parser)]
#[command(name = "laserlines-ros2", version, about, long_about = None)]
pub struct Ros2Args {
    /// Line extraction algorithm (hough-split, iterative-hough, split-and-merge, iepf,
    /// incremental, line-regression, ransac, em).
    #[arg(long, default_value = "hough-split")]
    pub algorithm: String,
    /// TOML file of parameters (one table per algorithm, e.g. `[hough-split]`), as
    /// `laserlines extract --params`.
    #[arg(long)]
    pub params: Option<PathBuf>,
    /// Start the extractor from one of its presets instead of its defaults (hough-split:
    /// paper, navigation, walls, complete), in place of any preset its table names, as
    /// `laserlines extract --preset`.
    #[arg(long)]
    pub preset: Option<String>,
    /// Topic of the `sensor_msgs/msg/LaserScan` input.
    #[arg(long, default_value = "/scan")]
    pub scan_topic: String,
    /// Topic of the `LineSegmentList` output.
    #[arg(long, default_value = "/line_segments")]
    pub lines_topic: String,
    /// Topic of the `visualization_msgs/msg/Marker` output (`LINE_LIST`).
    #[arg(long, default_value = "/line_markers")]
    pub markers_topic: String,
    /// Also publish the paper's three sector objects (left, front, right) as a
    /// `visualization_msgs/msg/MarkerArray`.
    #[arg(long)]
    pub sectors: bool,
    /// Topic of the sector objects (with `--sectors`).
    #[arg(long, default_value = "/line_sectors")]
    pub sectors_topic: String,
    /// Frame of the outputs, as laser_line_extraction's `frame_id` parameter (default: the
    /// scan's own frame). The stamp is always the scan's.
    #[arg(long)]
    pub frame_id: Option<String>,
    /// Package of the `LineSegmentList` type: `laser_line_extraction` (ROS 1 names and the
    /// message name laser_line_extraction's users subscribe to) or the package a port of it
    /// uses (e.g. `laser_line_extraction_interfaces`).
    #[arg(long, default_value = LINE_PACKAGE)]
    pub message_package: String,
    /// Node name.
    #[arg(long, default_value = "laserlines")]
    pub node_name: String,
    /// Node namespace.
    #[arg(long, default_value = "/")]
    pub namespace: String,
    /// DDS domain, 0..=232 (default: `ROS_DOMAIN_ID`, else 0).
    #[arg(long, allow_negative_numbers = true, value_parser = clap::value_parser!(u16).range(0..=232))]
    pub domain_id: Option<u16>,
    /// Talk to this host only (loopback); also set by `ROS_LOCALHOST_ONLY=1` or
    /// `ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST`.
    #[arg(long)]
    pub localhost_only: bool,
    /// Use only the network interface with this address (repeatable).
    #[arg(long = "interface", value_name = "ADDR")]
    pub interfaces: Vec<IpAddr>,
    /// Scans kept while the node is busy (subscription history depth, sensor data: 5), at
    /// least 1.
    #[arg(long, default_value_t = 5, allow_negative_numbers = true)]
    pub scan_depth: usize,
    /// Stop after this many scans (at least 1).
    #[arg(long, allow_negative_numbers = true, value_parser = clap::value_parser!(u64).range(1..))]
    pub scans: Option<u64>,
    /// Stop after this many seconds (more than 0).
    #[arg(long, allow_negative_numbers = true)]
    pub duration: Option<f64>,
    /// Log the counts (scans, lines per scan, extraction us) every this many seconds
    /// (0: only at the end).
    #[arg(long, default_value_t = 10.0, allow_negative_numbers = true)]
    pub status_every: f64,
}

/// The largest DDS domain whose ports fit in UDP's (7400 + 250 * domain + ...).
pub const MAX_DOMAIN_ID: u16 = 232;

/// True when an environment variable asks ROS 2 nodes to stay on this host; an error for
/// `ROS_AUTOMATIC_DISCOVERY_RANGE=OFF`, which turns discovery off: the node would hear no
/// publisher.
fn env_localhost_only() -> Result<bool> {
    let var = |k: &str| std::env::var(k).unwrap_or_default();
    let range = var("ROS_AUTOMATIC_DISCOVERY_RANGE");
    if range == "OFF" {
        bail!(
            "ROS_AUTOMATIC_DISCOVERY_RANGE=OFF turns discovery off, and this node finds its \
             publishers and subscribers by discovery only (no static peers): unset it, or \
             set it to LOCALHOST or SUBNET"
        );
    }
    Ok(var("ROS_LOCALHOST_ONLY") == "1" || range == "LOCALHOST")
}

fn seconds(name: &str, s: f64) -> Result<Duration> {
    Duration::try_from_secs_f64(s)
        .map_err(|_| anyhow::anyhow!("{name} must be a finite number of seconds >= 0, got {s}"))
}

/// True for a ROS 2 package name: lower-case letters, digits and underscores, from a letter
/// (REP 144).
fn is_package_name(name: &str) -> bool {
    name.starts_with(|c: char| c.is_ascii_lowercase())
        && name
            .chars()
            .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_')
}

/// The IPv4 addresses of this host's network interfaces, as RustDDS lists them (its
/// unicast transport is IPv4 only), sorted.
fn local_ipv4() -> Vec<Ipv4Addr> {
    let mut own: Vec<Ipv4Addr> = netdev::get_interfaces()
        .iter()
        .flat_map(|i| i.ipv4.iter().map(|net| net.addr()))
        .collect();
    own.sort_unstable();
    own.dedup();
    own
}

/// Fails unless `addr` is one of `own` ([`local_ipv4`]): DDS would otherwise start and talk
/// to nothing.
fn check_local(addr: IpAddr, own: &[Ipv4Addr]) -> Result<()> {
    let list = || {
        own.iter()
            .map(ToString::to_string)
            .collect::<Vec<_>>()
            .join(", ")
    };
    match addr {
        IpAddr::V4(v4) if own.contains(&v4) => Ok(()),
        IpAddr::V4(_) => bail!(
            "--interface {addr}: no network interface of this host has that address \
             (its IPv4 addresses: {})",
            list()
        ),
        IpAddr::V6(_) => bail!(
            "--interface {addr}: DDS here talks IPv4 only; give an IPv4 address of this \
             host (its IPv4 addresses: {})",
            list()
        ),
    }
}

impl Ros2Args {
    /// The node's configuration.
    ///
    /// # Errors
    /// A bad `ROS_DOMAIN_ID`, `--localhost-only` with `--interface`, or an `--interface`
    /// address no interface of this host has.
    pub fn node_config(&self) -> Result<NodeConfig> {
        let domain_id = self.domain_id()?;
        let only_networks = self.networks()?;
        if self.scan_depth == 0 {
            bail!("--scan-depth must be at least 1 (a DDS history of 0 scans keeps none)");
        }
        // A relative namespace is taken from the root, as `ros2 run --ros-args -r __ns:=`
        // takes it.
        let namespace = if self.namespace.starts_with('/') {
            self.namespace.clone()
        } else {
            format!("/{}", self.namespace)
        };
        let resolve = |topic: &str| {
            if topic.starts_with('/') {
                topic.to_owned()
            } else {
                format!("{}/{topic}", namespace.trim_end_matches('/'))
            }
        };
        self.check_outputs(&resolve)?;
        if !is_package_name(&self.message_package) {
            bail!(
                "--message-package must be a ROS 2 package name (lower-case letters, digits \
                 and underscores, from a letter), got {:?}",
                self.message_package
            );
        }
        // Topics resolved here (a relative one under the namespace), so that the node's log
        // names what it subscribes and publishes to.
        Ok(NodeConfig {
            node_name: self.node_name.clone(),
            scan_topic: resolve(&self.scan_topic),
            lines_topic: resolve(&self.lines_topic),
            markers_topic: resolve(&self.markers_topic),
            sectors_topic: self.sectors.then(|| resolve(&self.sectors_topic)),
            namespace,
            line_package: self.message_package.clone(),
            scan_depth: self.scan_depth,
            domain_id,
            only_networks,
        })
    }

    /// The DDS domain: `--domain-id`, else `ROS_DOMAIN_ID`, else 0.
    fn domain_id(&self) -> Result<u16> {
        let domain_id = match self.domain_id {
            Some(d) => d,
            None => match std::env::var("ROS_DOMAIN_ID") {
                Ok(s) if !s.trim().is_empty() => s
                    .trim()
                    .parse()
                    .with_context(|| format!("ROS_DOMAIN_ID must be 0..=232, got {s:?}"))?,
                _ => 0,
            },
        };
        if domain_id > MAX_DOMAIN_ID {
            bail!("the DDS domain must be 0..={MAX_DOMAIN_ID} (its UDP ports), got {domain_id}");
        }
        Ok(domain_id)
    }

    /// The networks the node talks on: loopback alone (`--localhost-only` or
    /// `ROS_LOCALHOST_ONLY`), the `--interface` addresses, or every one (`None`).
    fn networks(&self) -> Result<Option<Vec<IpAddr>>> {
        let localhost = self.localhost_only || env_localhost_only()?;
        if localhost && !self.interfaces.is_empty() {
            bail!("--interface and localhost-only (flag or environment) exclude each other");
        }
        Ok(if localhost {
            Some(vec![IpAddr::V4(Ipv4Addr::LOCALHOST)])
        } else if self.interfaces.is_empty() {
            None
        } else {
            let own = local_ipv4();
            for &addr in &self.interfaces {
                check_local(addr, &own)?;
            }
            Some(self.interfaces.clone())
        })
    }

    /// Refuses an output topic that is the scan topic or another output's (`resolve`d).
    fn check_outputs(&self, resolve: &dyn Fn(&str) -> String) -> Result<()> {
        let mut outputs = vec![
            ("--lines-topic", &self.lines_topic),
            ("--markers-topic", &self.markers_topic),
        ];
        if self.sectors {
            outputs.push(("--sectors-topic", &self.sectors_topic));
        }
        if let Some((_, same)) = outputs
            .iter()
            .find(|(_, t)| resolve(t) == resolve(&self.scan_topic))
        {
            bail!(
                "the output topic {same} is the scan topic {}: its messages would be read as \
                 LaserScans",
                self.scan_topic
            );
        }
        for (k, (a, ta)) in outputs.iter().enumerate() {
            if let Some((b, _)) = outputs[k + 1..]
                .iter()
                .find(|(_, tb)| resolve(tb) == resolve(ta))
            {
                bail!(
                    "{a} and {b} are both {}: two message types on one topic",
                    resolve(ta)
                );
            }
        }
        Ok(())
    }

    /// When the node stops by itself, and how often it logs.
    ///
    /// # Errors
    /// A negative or non-finite time.
    pub fn limits(&self) -> Result<Limits> {
        Ok(Limits {
            scans: self.scans,
            duration: self
                .duration
                .map(|s| match seconds("--duration", s) {
                    Ok(d) if !d.is_zero() => Ok(d),
                    _ => {
                        bail!("--duration must be a finite number of seconds more than 0, got {s}")
                    }
                })
                .transpose()?,
            status_every: Some(seconds("--status-every", self.status_every)?)
                .filter(|d| !d.is_zero()),
        })
    }

    /// The extractor, with the parameters file and the preset read exactly as
    /// `laserlines extract` reads them.
    ///
    /// # Errors
    /// An unknown algorithm or preset, or a bad params file (naming file, table and key).
    pub fn extractor(&self) -> Result<BoxedExtractor> {
        Ok(self.params_file()?.extractor(&self.algorithm)?)
    }

    /// The params file with the preset applied, read as `laserlines extract` reads them
    /// ([`ParamsFile::load_with_preset`]).
    ///
    /// # Errors
    /// An unknown algorithm or preset, or a params file that cannot be read.
    pub fn params_file(&self) -> Result<ParamsFile> {
        let (path, preset) = (self.params.as_deref(), self.preset.as_deref());
        Ok(ParamsFile::load_with_preset(path, &self.algorithm, preset)?)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn extractor(args: &[&str]) -> Result<BoxedExtractor> {
        let argv = std::iter::once("laserlines-ros2").chain(args.iter().copied());
        Ros2Args::try_parse_from(argv)?.extractor()
    }

    #[test]
    fn the_preset_option_is_read_as_the_cli_reads_it() {
        let argv = ["laserlines-ros2", "--preset", "complete"];
        let file = Ros2Args::try_parse_from(argv)
            .unwrap()
            .params_file()
            .unwrap();
        let p = file.algorithm_params(&laserlines::registry::HOUGH_SPLIT);
        assert_eq!(p.unwrap(), laserlines::HoughSplitParams::complete());
        assert_ne!(
            laserlines::HoughSplitParams::complete(),
            laserlines::HoughSplitParams::default()
        );
        assert_eq!(
            extractor(&["--preset", "walls"]).unwrap().name(),
            "hough-split"
        );
        let e = extractor(&["--preset", "wall"]).err().unwrap().to_string();
        assert_eq!(
            e,
            "unknown preset \"wall\" of hough-split: expected one of paper, navigation, walls, complete"
        );
        let e = extractor(&["--algorithm", "ransac", "--preset", "paper"])
            .err()
            .unwrap()
            .to_string();
        assert!(e.contains("of ransac: expected none"), "{e}");
    }

    fn config(args: &[&str]) -> Result<NodeConfig> {
        let argv = std::iter::once("laserlines-ros2").chain(args.iter().copied());
        Ros2Args::try_parse_from(argv)?.node_config()
    }

    #[test]
    fn namespaces_are_rooted_and_outputs_never_the_scan_topic() {
        assert_eq!(config(&["--namespace", "foo"]).unwrap().namespace, "/foo");
        assert_eq!(config(&["--namespace", "/foo"]).unwrap().namespace, "/foo");
        let e = config(&["--scan-depth", "0"]).err().unwrap().to_string();
        assert!(e.contains("--scan-depth must be at least 1"), "{e}");
        let e = config(&["--lines-topic", "/scan"])
            .err()
            .unwrap()
            .to_string();
        assert!(
            e.contains("the output topic /scan is the scan topic"),
            "{e}"
        );
        // Relative names resolve in the namespace.
        let e = config(&[
            "--namespace",
            "/r",
            "--scan-topic",
            "scan",
            "--markers-topic",
            "/r/scan",
        ])
        .err()
        .unwrap()
        .to_string();
        assert!(e.contains("is the scan topic scan"), "{e}");
        assert!(
            config(&[
                "--namespace",
                "/r",
                "--scan-topic",
                "scan",
                "--lines-topic",
                "/scan"
            ])
            .is_ok()
        );
    }

    #[test]
    fn topics_are_resolved_and_each_output_has_its_own() {
        let c = config(&["--namespace", "foo", "--scan-topic", "scan"]).unwrap();
        assert_eq!(c.scan_topic, "/foo/scan");
        assert_eq!(c.lines_topic, "/line_segments");
        let e = config(&["--markers-topic", "/line_segments"])
            .err()
            .unwrap()
            .to_string();
        assert!(
            e.contains("--lines-topic and --markers-topic are both /line_segments"),
            "{e}"
        );
        let e = config(&["--sectors", "--sectors-topic", "/line_markers"])
            .err()
            .unwrap()
            .to_string();
        assert!(
            e.contains("--markers-topic and --sectors-topic are both /line_markers"),
            "{e}"
        );
        // The sectors' topic is not used without --sectors.
        assert!(config(&["--sectors-topic", "/scan"]).is_ok());
        assert!(config(&["--sectors", "--sectors-topic", "/scan"]).is_err());
    }

    #[test]
    fn the_message_package_is_a_package_name() {
        for good in [
            "laser_line_extraction",
            "laser_line_extraction_interfaces",
            "a1",
        ] {
            assert!(config(&["--message-package", good]).is_ok(), "{good}");
        }
        for bad in ["x y", "", "Laser", "1a", "_a", "a/b"] {
            let e = config(&["--message-package", bad])
                .err()
                .unwrap()
                .to_string();
            assert!(
                e.contains("--message-package must be a ROS 2 package name"),
                "{e}"
            );
        }
    }

    #[test]
    fn an_interface_must_be_one_of_this_hosts() {
        assert!(config(&["--interface", "127.0.0.1"]).is_ok());
        // 192.0.2.0/24 is reserved for documentation (RFC 5737): no host has it.
        let refused = |addr: &str| config(&["--interface", addr]).err().unwrap().to_string();
        let e = refused("192.0.2.1");
        assert!(
            e.starts_with("--interface 192.0.2.1: no network interface of this host has that address (its IPv4 addresses: ")
                && e.contains("127.0.0.1"),
            "{e}"
        );
        // Bindable, but no interface's own address: DDS would hear nothing there.
        for addr in ["0.0.0.0", "127.0.0.2", "255.255.255.255"] {
            assert!(refused(addr).contains("no network interface"), "{addr}");
        }
        assert!(refused("::1").contains("DDS here talks IPv4 only"));
    }

    #[test]
    fn times_that_are_no_seconds_say_what_they_got() {
        let limits = |args: &[&str]| {
            let argv = std::iter::once("laserlines-ros2").chain(args.iter().copied());
            Ros2Args::try_parse_from(argv).unwrap().limits()
        };
        for (value, shown) in [("inf", "inf"), ("-1", "-1"), ("NaN", "NaN"), ("0", "0")] {
            let e = limits(&["--duration", value]).err().unwrap().to_string();
            assert_eq!(
                e,
                format!("--duration must be a finite number of seconds more than 0, got {shown}")
            );
        }
        let e = limits(&["--status-every", "-1"]).err().unwrap().to_string();
        assert_eq!(
            e,
            "--status-every must be a finite number of seconds >= 0, got -1"
        );
        assert!(
            limits(&["--status-every", "0"])
                .unwrap()
                .status_every
                .is_none()
        );
    }

    #[test]
    fn counts_out_of_range_name_their_option_and_range() {
        let refused = |args: &[&str]| {
            let argv = std::iter::once("laserlines-ros2").chain(args.iter().copied());
            Ros2Args::try_parse_from(argv).err().unwrap().to_string()
        };
        let e = refused(&["--domain-id", "-1"]);
        assert!(
            e.contains("'--domain-id <DOMAIN_ID>': -1 is not in 0..=232"),
            "{e}"
        );
        let e = refused(&["--domain-id", "233"]);
        assert!(e.contains("233 is not in 0..=232"), "{e}");
        let e = refused(&["--scans", "0"]);
        assert!(e.contains("'--scans <SCANS>': 0 is not in 1.."), "{e}");
        let e = refused(&["--scan-depth", "-3"]);
        assert!(e.contains("invalid value '-3' for '--scan-depth"), "{e}");
    }
}
