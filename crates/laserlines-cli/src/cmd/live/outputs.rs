//! Where the scans and lines of `live` go: the Foxglove live view, an MCAP recording, lines
//! JSONL, and with `--sectors` the three sector objects of each scan (printed, and on
//! `/sectors` in the view and the recording).

use std::fs::File;
use std::io::{BufWriter, Write};

use anyhow::Result;
use laserlines::Line;
use laserlines::math::Isometry2;
use laserlines_foxglove::LinesOutput;
use laserlines_foxglove::live::LiveServer;
use laserlines_foxglove::scene::SceneClock;
use laserlines_foxglove::sectors::{SECTORS_TOPIC, sectors_update};
use laserlines_foxglove::write::McapSceneWriter;
use laserlines_foxglove::{LASER_FRAME, messages::SceneUpdate};
use laserlines_io::ScanRecord;
use laserlines_nav::sectors::{Sector, SectorObjects, SectorParams, select_objects};

use super::LiveArgs;

/// The outputs chosen on the command line.
pub struct Outputs {
    server: Option<LiveServer>,
    recording: Option<McapSceneWriter<BufWriter<File>>>,
    output: Option<LinesOutput>,
    sectors: bool,
    clock: SceneClock,
}

impl Outputs {
    /// Starts the live view and creates the files asked for.
    pub fn open(args: &LiveArgs) -> Result<Self> {
        let server = if args.view {
            let topics: &[&str] = if args.sectors { &[SECTORS_TOPIC] } else { &[] };
            let server = LiveServer::start_with_scenes("127.0.0.1", args.port, topics)?;
            outln!(
                "laserlines: serving ws://127.0.0.1:{} (in Foxglove: Open connection, Foxglove WebSocket)",
                server.port()
            );
            std::io::stdout().flush()?;
            Some(server)
        } else {
            None
        };
        let recording = args
            .record
            .as_deref()
            .map(McapSceneWriter::create)
            .transpose()?;
        let output = args
            .output
            .as_deref()
            .map(LinesOutput::create)
            .transpose()?;
        Ok(Self {
            server,
            recording,
            output,
            sectors: args.sectors,
            clock: SceneClock::new(),
        })
    }

    /// Sends scan `k` and its lines to every output.
    pub fn publish(&mut self, k: u64, record: &ScanRecord, lines: &[Line]) -> Result<()> {
        let time = self.clock.time_of(record.scan.stamp);
        if let Some(s) = &self.server {
            s.publish(record, lines, time);
        }
        if let Some(w) = &mut self.recording {
            w.write_lines(record, lines)?;
        }
        if let Some(o) = &mut self.output {
            o.write_record(k, record, lines)?;
        }
        if self.sectors {
            // The sensor stands for the robot: the sectors are measured from the laser.
            let objects = select_objects(lines, &Isometry2::identity(), &SectorParams::default());
            outln!("{}", describe_sectors(k, &objects));
            if self.server.is_some() || self.recording.is_some() {
                let update = sectors_update(&objects, LASER_FRAME, None, time);
                self.publish_sectors(&update, time)?;
            }
        }
        Ok(())
    }

    fn publish_sectors(&mut self, update: &SceneUpdate, time: f64) -> Result<()> {
        if let Some(s) = &self.server {
            s.publish_scene(SECTORS_TOPIC, update, time)?;
        }
        if let Some(w) = &mut self.recording {
            w.write_message(SECTORS_TOPIC, update, time)?;
        }
        Ok(())
    }

    /// Finishes the recording and the lines file, and stops the live view.
    pub fn close(self) -> Result<()> {
        let recorded = self.recording.map(McapSceneWriter::finish).transpose();
        let written = self.output.map(LinesOutput::close).transpose();
        if let Some(s) = self.server {
            s.stop();
        }
        recorded?;
        written?;
        Ok(())
    }
}

/// The three sector objects of scan `k` as one line of text.
fn describe_sectors(k: u64, objects: &SectorObjects) -> String {
    let parts: Vec<String> = [Sector::Left, Sector::Front, Sector::Right]
        .iter()
        .map(|&s| match objects.get(s) {
            Some(o) => format!(
                "{}: distance {:.3} m, width {:.3} m, line direction {:.1} deg",
                s.name(),
                o.distance_m,
                o.width_m,
                o.angle_rad.to_degrees()
            ),
            None => format!("{}: none", s.name()),
        })
        .collect();
    format!("scan {k}: {}", parts.join("; "))
}
