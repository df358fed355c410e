//! What an emulated sensor says about itself.

use std::fmt;
use std::str::FromStr;

/// The models the emulator knows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ModelName {
    /// Hokuyo URG-04LX: 682 steps of 360/1024 deg (44..=725, front 384), 20..5600 mm,
    /// 600 rpm (10 scans/s), USB serial.
    Urg04lx,
    /// Hokuyo UST-10LX: 1081 steps of 0.25 deg (0..=1080, front 540, 270 deg),
    /// 20..10000 mm (the data sheet guarantees 0.06..10 m), 2400 rpm (40 scans/s), TCP.
    Ust10lx,
}

impl ModelName {
    /// The names `--model` takes.
    pub const NAMES: [&'static str; 2] = ["urg-04lx", "ust-10lx"];
}

impl FromStr for ModelName {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.to_ascii_lowercase().as_str() {
            "urg-04lx" | "urg04lx" => Ok(Self::Urg04lx),
            "ust-10lx" | "ust10lx" => Ok(Self::Ust10lx),
            _ => Err(format!(
                "unknown model {s:?}: expected one of {}",
                Self::NAMES.join(", ")
            )),
        }
    }
}

impl fmt::Display for ModelName {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::Urg04lx => "urg-04lx",
            Self::Ust10lx => "ust-10lx",
        })
    }
}

/// The emulated sensor's description: what `VV`, `PP` and `II` report.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Model {
    /// Which model.
    pub name: ModelName,
    /// `VEND`.
    pub vendor: String,
    /// `PROD`.
    pub product: String,
    /// `FIRM`.
    pub firmware: String,
    /// `PROT`.
    pub protocol: String,
    /// `SERI`.
    pub serial: String,
    /// `MODL`.
    pub model: String,
    /// `DMIN`, mm.
    pub dmin_mm: u32,
    /// `DMAX`, mm.
    pub dmax_mm: u32,
    /// `ARES`.
    pub ares: u32,
    /// `AMIN`.
    pub amin: u32,
    /// `AMAX`.
    pub amax: u32,
    /// `AFRT`.
    pub afrt: u32,
    /// `SCAN`, rpm.
    pub scan_rpm: u32,
    /// The bit rate `II` reports, bit/s.
    pub bit_rate: u32,
}

impl Model {
    /// The model's description.
    #[must_use]
    pub fn new(name: ModelName) -> Self {
        match name {
            ModelName::Urg04lx => Self {
                name,
                vendor: "Hokuyo Automatic Co., Ltd.".to_owned(),
                product: "SOKUIKI Sensor URG-04LX".to_owned(),
                firmware: "3.4.03 (laserlines emulator)".to_owned(),
                protocol: "SCIP 2.0".to_owned(),
                serial: "H0000000".to_owned(),
                model: "URG-04LX(Hokuyo Automatic Co., Ltd.)".to_owned(),
                dmin_mm: 20,
                dmax_mm: 5600,
                ares: 1024,
                amin: 44,
                amax: 725,
                afrt: 384,
                scan_rpm: 600,
                bit_rate: 115_200,
            },
            ModelName::Ust10lx => Self {
                name,
                vendor: "Hokuyo Automatic Co., Ltd.".to_owned(),
                product: "SOKUIKI Sensor UST-10LX".to_owned(),
                firmware: "1.0.0 (laserlines emulator)".to_owned(),
                protocol: "SCIP 2.2".to_owned(),
                serial: "H0000000".to_owned(),
                model: "UST-10LX".to_owned(),
                dmin_mm: 20,
                dmax_mm: 10_000,
                ares: 1440,
                amin: 0,
                amax: 1080,
                afrt: 540,
                scan_rpm: 2400,
                bit_rate: 115_200,
            },
        }
    }

    /// Steps `AMIN..=AMAX`.
    #[must_use]
    pub fn steps(&self) -> usize {
        (self.amax - self.amin + 1) as usize
    }

    /// One scan, ms.
    #[must_use]
    pub fn period_ms(&self) -> u64 {
        60_000 / u64::from(self.scan_rpm.max(1))
    }

    /// The angle of step `step`, rad.
    #[must_use]
    pub fn step_angle(&self, step: u32) -> f64 {
        (f64::from(step) - f64::from(self.afrt)) * std::f64::consts::TAU / f64::from(self.ares)
    }
}
