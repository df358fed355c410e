//! What the sensor says about itself (`VV`, `PP`, `II`), the scan geometry that follows
//! from it, and the meaning of the readings below `DMIN`.

use std::f64::consts::TAU;

use crate::request::{MAX_STEP, ScanRequest};

/// A missing or malformed parameter in the sensor's description.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum InfoError {
    /// A parameter the geometry needs is missing from the `PP` reply.
    #[error("PP reply has no {0} parameter")]
    Missing(&'static str),
    /// A parameter is not a whole number.
    #[error("PP parameter {key} = {value:?} is not a whole number")]
    NotANumber {
        /// The label.
        key: &'static str,
        /// Its value.
        value: String,
    },
    /// The parameters contradict each other.
    #[error("PP parameters are inconsistent: {0}")]
    Inconsistent(String),
}

/// The sensor's description: version information (`VV`), parameters (`PP`) and state
/// (`II`). The scan geometry comes from `ARES`, `AMIN`, `AMAX` and `AFRT`, the range limits
/// from `DMIN` and `DMAX`, the scan period from `SCAN`; nothing is assumed per model.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct SensorInfo {
    /// `VEND`: the vendor.
    pub vendor: String,
    /// `PROD`: the product.
    pub product: String,
    /// `FIRM`: the firmware version.
    pub firmware: String,
    /// `PROT`: the protocol version.
    pub protocol: String,
    /// `SERI`: the serial number.
    pub serial: String,
    /// `MODL`: the model.
    pub model: String,
    /// `DMIN`: smallest valid range, mm; smaller readings are error codes.
    pub dmin_mm: u32,
    /// `DMAX`: largest valid range, mm.
    pub dmax_mm: u32,
    /// `ARES`: steps in a full turn.
    pub ares: u32,
    /// `AMIN`: first measured step.
    pub amin: u32,
    /// `AMAX`: last measured step.
    pub amax: u32,
    /// `AFRT`: the step pointing forward (x axis).
    pub afrt: u32,
    /// `SCAN`: motor speed, rpm (one scan per turn).
    pub scan_rpm: u32,
    /// Every `II` pair as sent (laser state, motor speed, time, ...).
    pub state: Vec<(String, String)>,
}

fn lookup<'a>(pairs: &'a [(String, String)], key: &str) -> Option<&'a str> {
    pairs
        .iter()
        .find(|(k, _)| k == key)
        .map(|(_, v)| v.as_str())
}

fn number(pairs: &[(String, String)], key: &'static str) -> Result<u32, InfoError> {
    let v = lookup(pairs, key).ok_or(InfoError::Missing(key))?;
    // Some sensors pad the value ("DMIN: 20") or follow it with a unit.
    let digits: String = v.trim().chars().take_while(char::is_ascii_digit).collect();
    digits.parse().map_err(|_| InfoError::NotANumber {
        key,
        value: v.to_owned(),
    })
}

impl SensorInfo {
    /// The description from the `LABEL:VALUE` pairs of the `VV`, `PP` and `II` replies.
    ///
    /// # Errors
    /// [`InfoError`] when a `PP` parameter the geometry needs is missing, not a number, or
    /// inconsistent (`ARES` 0, `AMIN > AMAX`, `AMAX >= ARES`, `AMAX` above [`MAX_STEP`]
    /// (no command could ask for it), `DMIN >= DMAX`, `SCAN` 0).
    pub fn from_pairs(
        vv: &[(String, String)],
        pp: &[(String, String)],
        ii: &[(String, String)],
    ) -> Result<Self, InfoError> {
        let text = |pairs: &[(String, String)], k: &str| lookup(pairs, k).unwrap_or("").to_owned();
        let info = Self {
            vendor: text(vv, "VEND"),
            product: text(vv, "PROD"),
            firmware: text(vv, "FIRM"),
            protocol: text(vv, "PROT"),
            serial: text(vv, "SERI"),
            model: text(pp, "MODL"),
            dmin_mm: number(pp, "DMIN")?,
            dmax_mm: number(pp, "DMAX")?,
            ares: number(pp, "ARES")?,
            amin: number(pp, "AMIN")?,
            amax: number(pp, "AMAX")?,
            afrt: number(pp, "AFRT")?,
            scan_rpm: number(pp, "SCAN")?,
            state: ii.to_vec(),
        };
        if info.ares == 0 || info.amin > info.amax || info.amax >= info.ares {
            return Err(InfoError::Inconsistent(format!(
                "steps AMIN {} .. AMAX {} of ARES {}",
                info.amin, info.amax, info.ares
            )));
        }
        if info.amax > MAX_STEP {
            return Err(InfoError::Inconsistent(format!(
                "AMAX {} is beyond step {MAX_STEP}, the last a command can name (4 digits)",
                info.amax
            )));
        }
        if info.dmin_mm >= info.dmax_mm {
            return Err(InfoError::Inconsistent(format!(
                "DMIN {} mm is not below DMAX {} mm",
                info.dmin_mm, info.dmax_mm
            )));
        }
        if info.scan_rpm == 0 {
            return Err(InfoError::Inconsistent("SCAN is 0 rpm".to_owned()));
        }
        Ok(info)
    }

    /// The angle of step `step` (may be fractional), rad, counter-clockwise from the
    /// forward step `AFRT`.
    #[must_use]
    pub fn step_angle(&self, step: f64) -> f64 {
        (step - f64::from(self.afrt)) * TAU / f64::from(self.ares)
    }

    /// One step, rad.
    #[must_use]
    pub fn step_rad(&self) -> f64 {
        TAU / f64::from(self.ares)
    }

    /// Time of one motor turn (one scan), s.
    #[must_use]
    pub fn scan_period_s(&self) -> f64 {
        60.0 / f64::from(self.scan_rpm)
    }

    /// The smallest valid range, m.
    #[must_use]
    pub fn range_min_m(&self) -> f64 {
        f64::from(self.dmin_mm) / 1000.0
    }

    /// The largest valid range, m.
    #[must_use]
    pub fn range_max_m(&self) -> f64 {
        f64::from(self.dmax_mm) / 1000.0
    }

    /// The whole measurement area: `AMIN..=AMAX`, every step, `MD` (3 characters).
    #[must_use]
    pub fn full_request(&self) -> ScanRequest {
        ScanRequest::new(self.amin, self.amax)
    }

    /// The geometry of the scans `request` gives: angle of the first beam, increment and
    /// beam count. With a cluster count `c > 1` each beam stands for `c` steps and points
    /// at their middle.
    #[must_use]
    pub fn geometry(&self, request: &ScanRequest) -> ScanGeometry {
        let c = request.cluster_steps();
        let beams = request.values();
        let first = f64::from(request.first_step) + (f64::from(c) - 1.0) / 2.0;
        ScanGeometry {
            angle_min: self.step_angle(first),
            angle_increment: self.step_rad() * f64::from(c),
            beams,
        }
    }
}

/// Where the beams of a scan point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScanGeometry {
    /// Angle of the first beam, rad.
    pub angle_min: f64,
    /// Angle between beams, rad.
    pub angle_increment: f64,
    /// Number of beams.
    pub beams: usize,
}

/// Why a reading is not a range: the error codes a Hokuyo sends in place of ranges below
/// `DMIN` (URG-04LX, UBG-04LX-F01, UHG-08LX tables), or a reading beyond `DMAX`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum NoReturn {
    /// Code 0: no echo; the object is possibly at about 22 m (or beyond the range).
    PossiblyFar,
    /// Codes 1 to 5: the reflected light has low intensity.
    LowIntensity(u8),
    /// Code 6: the object is possibly at about 5.7 m.
    PossiblyAt5700Mm,
    /// Code 7: the steps before and after have errors.
    NeighboursInError,
    /// Code 8: intensity difference of the two waves.
    TwoWaveDifference,
    /// Code 9: the same step failed in the last two scans.
    SameStepFailedTwice,
    /// Code 16: the object is possibly at about 4096 mm.
    PossiblyAt4096Mm,
    /// Code 18: reading error due to a strongly reflective object.
    StrongReflector,
    /// Code 19: the step cannot be measured.
    NonMeasurable,
    /// Another code below `DMIN` (10 to 15, 17, and 20 and up on sensors whose `DMIN` is
    /// larger).
    Other(u32),
    /// A reading beyond `DMAX`.
    BeyondMax,
}

impl NoReturn {
    /// Why `mm` is not a range for a sensor measuring `dmin..=dmax` mm, or `None` when it is
    /// a range.
    #[must_use]
    pub fn classify(mm: u32, dmin: u32, dmax: u32) -> Option<Self> {
        if mm > dmax {
            return Some(Self::BeyondMax);
        }
        if mm >= dmin {
            return None;
        }
        Some(match mm {
            0 => Self::PossiblyFar,
            1..=5 => Self::LowIntensity(mm as u8),
            6 => Self::PossiblyAt5700Mm,
            7 => Self::NeighboursInError,
            8 => Self::TwoWaveDifference,
            9 => Self::SameStepFailedTwice,
            16 => Self::PossiblyAt4096Mm,
            18 => Self::StrongReflector,
            19 => Self::NonMeasurable,
            other => Self::Other(other),
        })
    }

    /// A short description.
    #[must_use]
    pub fn describe(&self) -> &'static str {
        match self {
            Self::PossiblyFar => "no echo (possibly at 22 m)",
            Self::LowIntensity(_) => "low intensity",
            Self::PossiblyAt5700Mm => "possibly at 5.7 m",
            Self::NeighboursInError => "neighbouring steps in error",
            Self::TwoWaveDifference => "intensity difference of two waves",
            Self::SameStepFailedTwice => "same step failed twice",
            Self::PossiblyAt4096Mm => "possibly at 4096 mm",
            Self::StrongReflector => "strong reflector",
            Self::NonMeasurable => "non-measurable step",
            Self::Other(_) => "other error code",
            Self::BeyondMax => "beyond DMAX",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pairs(list: &[(&str, &str)]) -> Vec<(String, String)> {
        list.iter()
            .map(|(k, v)| ((*k).to_owned(), (*v).to_owned()))
            .collect()
    }

    fn urg04lx_pp() -> Vec<(String, String)> {
        pairs(&[
            ("MODL", "URG-04LX(Hokuyo Automatic Co., Ltd.)"),
            ("DMIN", "20"),
            ("DMAX", "5600"),
            ("ARES", "1024"),
            ("AMIN", "44"),
            ("AMAX", "725"),
            ("AFRT", "384"),
            ("SCAN", "600"),
        ])
    }

    #[test]
    fn the_urg04lx_parameters_give_the_papers_geometry() {
        let vv = pairs(&[("SERI", "H0000001"), ("PROD", "SOKUIKI Sensor URG-04LX")]);
        let info = SensorInfo::from_pairs(&vv, &urg04lx_pp(), &[]).unwrap();
        assert_eq!(info.serial, "H0000001");
        let g = info.geometry(&info.full_request());
        assert_eq!(g.beams, 682);
        let inc = TAU / 1024.0;
        assert!((g.angle_increment - inc).abs() < 1e-15);
        assert!((g.angle_min - (-340.0 * inc)).abs() < 1e-12);
        assert!((info.scan_period_s() - 0.1).abs() < 1e-12);
        // Cluster of 3 from step 44: beams at the middle steps 45, 48, ...; 228 beams.
        let g3 = info.geometry(&ScanRequest {
            cluster: 3,
            ..info.full_request()
        });
        assert_eq!(g3.beams, 228);
        assert!((g3.angle_min - (-339.0 * inc)).abs() < 1e-12);
        assert!((g3.angle_increment - 3.0 * inc).abs() < 1e-15);
    }

    #[test]
    fn bad_parameters_are_named() {
        let mut pp = urg04lx_pp();
        pp.retain(|(k, _)| k != "AFRT");
        assert_eq!(
            SensorInfo::from_pairs(&[], &pp, &[]),
            Err(InfoError::Missing("AFRT"))
        );
        let mut pp = urg04lx_pp();
        pp[2].1 = "lots".to_owned();
        assert!(matches!(
            SensorInfo::from_pairs(&[], &pp, &[]),
            Err(InfoError::NotANumber { key: "DMAX", .. })
        ));
        let mut pp = urg04lx_pp();
        pp[5].1 = "2000".to_owned();
        assert!(matches!(
            SensorInfo::from_pairs(&[], &pp, &[]),
            Err(InfoError::Inconsistent(_))
        ));
    }

    #[test]
    fn error_codes_keep_their_reason() {
        assert_eq!(NoReturn::classify(0, 20, 5600), Some(NoReturn::PossiblyFar));
        assert_eq!(
            NoReturn::classify(3, 20, 5600),
            Some(NoReturn::LowIntensity(3))
        );
        assert_eq!(
            NoReturn::classify(6, 20, 5600),
            Some(NoReturn::PossiblyAt5700Mm)
        );
        assert_eq!(
            NoReturn::classify(16, 20, 5600),
            Some(NoReturn::PossiblyAt4096Mm)
        );
        assert_eq!(NoReturn::classify(12, 20, 5600), Some(NoReturn::Other(12)));
        assert_eq!(NoReturn::classify(20, 20, 5600), None);
        assert_eq!(NoReturn::classify(5600, 20, 5600), None);
        assert_eq!(
            NoReturn::classify(5601, 20, 5600),
            Some(NoReturn::BeyondMax)
        );
    }
}
