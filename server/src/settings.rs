//! The service's configuration: one TOML file (`trackd.toml`), overridden by `TRACKD_*`
//! environment variables and flags.

use std::{net::SocketAddr, path::Path};

use anyhow::Context;
use nalgebra::{Isometry3, Matrix3, Rotation3, Translation3, UnitQuaternion};
use serde::{Deserialize, Serialize};
use trackd_perception::{config::Config, fleet::FusionConfig, geo::GeoOrigin};

/// The commented service part of the default file; the `[perception]` table is appended from
/// the built-in defaults by [`Settings::default_file`].
const SERVICE_DEFAULTS: &str = include_str!("default_config.toml");

/// Everything `trackd serve` needs.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Settings {
    /// Who this vehicle is.
    pub vehicle: VehicleSettings,
    /// The REST API.
    pub http: HttpSettings,
    /// The scan queue.
    pub queue: QueueSettings,
    /// The Zenoh session.
    pub zenoh: ZenohSettings,
    /// Fleet fusion.
    pub fleet: FleetSettings,
    /// Write access.
    pub auth: AuthSettings,
    /// The perception pipeline.
    pub perception: Config,
}

/// `[vehicle]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct VehicleSettings {
    /// The vehicle's id in the fleet.
    pub id: String,
    /// KITTI's `Tr_imu_to_velo`: rotation row-major (9 values), then translation (3).
    pub imu_to_velo: [f64; 12],
}

impl Default for VehicleSettings {
    fn default() -> Self {
        Self {
            id: "vehicle-1".into(),
            imu_to_velo: [
                0.9999976,
                0.0007553071,
                -0.002035826,
                -0.0007854027,
                0.9998898,
                -0.01482298,
                0.002024406,
                0.01482454,
                0.9998881,
                -0.8086759,
                0.3195559,
                -0.7997231,
            ],
        }
    }
}

impl VehicleSettings {
    /// Sets `imu_to_velo` from a rigid transform.
    pub fn set_imu_to_velo(&mut self, t: &Isometry3<f64>) {
        let r = t.rotation.to_rotation_matrix();
        let m = r.matrix();
        let v = t.translation.vector;
        self.imu_to_velo = [
            m[(0, 0)],
            m[(0, 1)],
            m[(0, 2)],
            m[(1, 0)],
            m[(1, 1)],
            m[(1, 2)],
            m[(2, 0)],
            m[(2, 1)],
            m[(2, 2)],
            v.x,
            v.y,
            v.z,
        ];
    }

    /// `imu_to_velo` as a rigid transform (the rotation re-orthonormalised).
    pub fn imu_to_velo(&self) -> Isometry3<f64> {
        let m = &self.imu_to_velo;
        let r = Matrix3::new(m[0], m[1], m[2], m[3], m[4], m[5], m[6], m[7], m[8]);
        let rotation = Rotation3::from_matrix(&r);
        Isometry3::from_parts(
            Translation3::new(m[9], m[10], m[11]),
            UnitQuaternion::from_rotation_matrix(&rotation),
        )
    }
}

/// `[http]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct HttpSettings {
    /// Address of the REST API.
    pub listen: SocketAddr,
    /// Largest accepted request body (bytes).
    pub max_body_bytes: usize,
    /// How long a synchronous upload waits for its result (ms).
    pub result_timeout_ms: u64,
}

impl Default for HttpSettings {
    fn default() -> Self {
        Self {
            listen: SocketAddr::from(([127, 0, 0, 1], 8080)),
            max_body_bytes: 16 * 1024 * 1024,
            result_timeout_ms: 10_000,
        }
    }
}

/// `[queue]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct QueueSettings {
    /// Scans waiting for the worker.
    pub capacity: usize,
    /// Positions kept per track.
    pub history: usize,
}

impl Default for QueueSettings {
    fn default() -> Self {
        Self {
            capacity: 8,
            history: 200,
        }
    }
}

/// How the Zenoh session joins the fleet.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize, clap::ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum ZenohMode {
    /// Talks to other peers directly and to routers.
    #[default]
    Peer,
    /// Talks only through a router.
    Client,
}

impl ZenohMode {
    /// Zenoh's name for the mode.
    pub fn as_str(&self) -> &'static str {
        match self {
            Self::Peer => "peer",
            Self::Client => "client",
        }
    }
}

/// `[zenoh]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ZenohSettings {
    /// Peer or client.
    pub mode: ZenohMode,
    /// Endpoints to listen on.
    pub listen: Vec<String>,
    /// Endpoints to connect to.
    pub connect: Vec<String>,
    /// UDP multicast scouting (off by default).
    pub multicast_scouting: bool,
    /// Larger super frames are dropped.
    pub max_message_bytes: usize,
}

impl Default for ZenohSettings {
    fn default() -> Self {
        Self {
            mode: ZenohMode::Peer,
            listen: vec!["tcp/127.0.0.1:7447".into()],
            connect: Vec::new(),
            multicast_scouting: false,
            max_message_bytes: 4 * 1024 * 1024,
        }
    }
}

impl ZenohSettings {
    /// The Zenoh configuration of these settings (timestamps on, so lag can be measured).
    pub fn to_zenoh_config(&self) -> anyhow::Result<zenoh::Config> {
        zenoh_config(
            self.mode.as_str(),
            &self.listen,
            &self.connect,
            self.multicast_scouting,
        )
    }
}

/// A Zenoh configuration: `mode`, explicit endpoints, multicast scouting as given, and
/// timestamps on every publication (so receive lag can be measured).
pub fn zenoh_config(
    mode: &str,
    listen: &[String],
    connect: &[String],
    multicast_scouting: bool,
) -> anyhow::Result<zenoh::Config> {
    let mut config = zenoh::Config::default();
    for (key, value) in [
        ("mode", serde_json::to_string(mode)?),
        (
            "scouting/multicast/enabled",
            serde_json::to_string(&multicast_scouting)?,
        ),
        ("listen/endpoints", serde_json::to_string(listen)?),
        ("connect/endpoints", serde_json::to_string(connect)?),
        ("timestamping/enabled", "true".to_string()),
    ] {
        config
            .insert_json5(key, &value)
            .map_err(|e| anyhow::anyhow!("zenoh config {key} = {value}: {e}"))?;
    }
    Ok(config)
}

/// `[fleet]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct FleetSettings {
    /// The fleet's geodetic origin `[lat, lon, alt]`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub origin: Option<[f64; 3]>,
    /// Silence (ms) after which a vehicle's objects expire.
    pub ttl_ms: u64,
    /// Association gate on the ground (m).
    pub gate_m: f64,
    /// Largest accepted distance between a super frame's origin and the fleet's (m).
    pub max_origin_offset_m: f64,
    /// Largest accepted number of objects per super frame.
    pub max_objects: usize,
    /// Largest accepted object distance from its origin (m).
    pub max_range_m: f64,
    /// Longest prediction of a remote object along its velocity (ms).
    pub max_prediction_ms: u64,
}

impl Default for FleetSettings {
    fn default() -> Self {
        let f = FusionConfig::default();
        Self {
            origin: None,
            ttl_ms: f.ttl_ms,
            gate_m: f.gate_m,
            max_origin_offset_m: f.max_origin_offset_m,
            max_objects: f.max_objects,
            max_range_m: f.max_range_m,
            max_prediction_ms: f.max_prediction_ms,
        }
    }
}

impl FleetSettings {
    /// The fleet origin, if configured.
    pub fn origin(&self) -> Option<GeoOrigin> {
        self.origin
            .map(|[lat, lon, alt]| GeoOrigin::new(lat, lon, alt))
    }

    /// The fusion thresholds.
    pub fn fusion(&self) -> FusionConfig {
        FusionConfig {
            ttl_ms: self.ttl_ms,
            gate_m: self.gate_m,
            max_origin_offset_m: self.max_origin_offset_m,
            max_objects: self.max_objects,
            max_range_m: self.max_range_m,
            max_prediction_ms: self.max_prediction_ms,
        }
    }
}

/// `[auth]`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct AuthSettings {
    /// Bearer token for writes; empty: none needed.
    pub token: String,
}

/// Flags (and `TRACKD_*` variables) that override the file.
#[derive(Clone, Debug, Default, clap::Args)]
pub struct SettingsFlags {
    /// Configuration file (TOML); without it, the built-in defaults.
    #[arg(long, env = "TRACKD_CONFIG")]
    pub config: Option<std::path::PathBuf>,
    /// Vehicle id.
    #[arg(long, env = "TRACKD_VEHICLE")]
    pub vehicle: Option<String>,
    /// REST API address, e.g. 0.0.0.0:8080.
    #[arg(long, env = "TRACKD_HTTP")]
    pub http: Option<SocketAddr>,
    /// Zenoh mode.
    #[arg(long, value_enum, env = "TRACKD_MODE")]
    pub mode: Option<ZenohMode>,
    /// Zenoh endpoint to listen on (repeatable; replaces the file's list).
    #[arg(long, env = "TRACKD_LISTEN", value_delimiter = ',')]
    pub listen: Vec<String>,
    /// Zenoh endpoint to connect to (repeatable; replaces the file's list).
    #[arg(long, env = "TRACKD_CONNECT", value_delimiter = ',')]
    pub connect: Vec<String>,
    /// Fleet origin LAT,LON,ALT (degrees, degrees, metres).
    #[arg(long, env = "TRACKD_ORIGIN", value_parser = parse_origin, allow_hyphen_values = true)]
    pub origin: Option<[f64; 3]>,
    /// Bearer token required by writes.
    #[arg(long, env = "TRACKD_TOKEN")]
    pub token: Option<String>,
    /// Fleet TTL (ms).
    #[arg(long, env = "TRACKD_TTL_MS")]
    pub ttl_ms: Option<u64>,
    /// Scan queue capacity.
    #[arg(long, env = "TRACKD_QUEUE")]
    pub queue: Option<usize>,
}

/// Parses `LAT,LON,ALT`.
pub fn parse_origin(text: &str) -> Result<[f64; 3], String> {
    let values: Vec<f64> = text
        .split(',')
        .map(|v| v.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|e| format!("origin {text:?}: {e}"))?;
    match values.as_slice() {
        [lat, lon, alt] => Ok([*lat, *lon, *alt]),
        _ => Err(format!("origin {text:?}: expected LAT,LON,ALT")),
    }
}

impl Settings {
    /// The whole default file, with comments: what `trackd config --print-default` prints.
    pub fn default_file() -> String {
        #[derive(Serialize)]
        struct PerceptionOnly<'a> {
            perception: &'a Config,
        }
        let perception = toml::to_string(&PerceptionOnly {
            perception: &Config::default(),
        })
        .unwrap_or_default();
        let perception = if perception.trim().is_empty() {
            "[perception]\n".to_string()
        } else {
            perception
        };
        format!("{SERVICE_DEFAULTS}{perception}")
    }

    /// Parses a TOML text.
    pub fn from_toml(text: &str) -> anyhow::Result<Self> {
        Ok(toml::from_str(text)?)
    }

    /// Reads a TOML file.
    pub fn read(path: &Path) -> anyhow::Result<Self> {
        let text =
            std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
        Self::from_toml(&text).with_context(|| format!("parsing {}", path.display()))
    }

    /// The file (or defaults) with `flags` applied, checked.
    pub fn load(flags: &SettingsFlags) -> anyhow::Result<Self> {
        let mut settings = match &flags.config {
            Some(path) => Self::read(path)?,
            None => Self::default(),
        };
        settings.apply(flags);
        settings.check()?;
        Ok(settings)
    }

    /// Applies the flags that were given.
    pub fn apply(&mut self, flags: &SettingsFlags) {
        if let Some(v) = &flags.vehicle {
            self.vehicle.id = v.clone();
        }
        if let Some(v) = flags.http {
            self.http.listen = v;
        }
        if let Some(v) = flags.mode {
            self.zenoh.mode = v;
        }
        if !flags.listen.is_empty() {
            self.zenoh.listen = flags.listen.clone();
        }
        if !flags.connect.is_empty() {
            self.zenoh.connect = flags.connect.clone();
        }
        if let Some(v) = flags.origin {
            self.fleet.origin = Some(v);
        }
        if let Some(v) = &flags.token {
            self.auth.token = v.clone();
        }
        if let Some(v) = flags.ttl_ms {
            self.fleet.ttl_ms = v;
        }
        if let Some(v) = flags.queue {
            self.queue.capacity = v;
        }
    }

    /// Refuses settings the service cannot run with.
    pub fn check(&self) -> anyhow::Result<()> {
        anyhow::ensure!(
            trackd_perception::fleet::is_valid_vehicle_id(&self.vehicle.id),
            "vehicle id {:?}: use 1-64 letters, digits, '_', '-' or '.'",
            self.vehicle.id
        );
        anyhow::ensure!(self.queue.capacity > 0, "queue.capacity must be at least 1");
        if let Some(origin) = self.fleet.origin() {
            anyhow::ensure!(
                trackd_perception::fleet::is_plausible(&origin),
                "fleet.origin {:?} is no place on Earth (|lat| <= 85, |lon| <= 180)",
                self.fleet.origin
            );
        }
        anyhow::ensure!(
            self.zenoh.mode != ZenohMode::Client || !self.zenoh.connect.is_empty(),
            "zenoh client mode needs a router to connect to (--connect)"
        );
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_file_parses_to_exactly_the_defaults() {
        let parsed = Settings::from_toml(&Settings::default_file()).expect("default file parses");
        assert_eq!(parsed, Settings::default());
    }

    #[test]
    fn every_default_key_is_in_the_default_file() {
        // Serialising the defaults and parsing them back is the identity, and every top-level
        // key written appears in the commented file.
        let text = toml::to_string(&Settings::default()).expect("serialises");
        let file = Settings::default_file();
        for line in text.lines() {
            if let Some((key, _)) = line.split_once(" = ") {
                assert!(file.contains(&format!("{key} = ")), "{key} missing");
            } else if line.starts_with('[') {
                assert!(file.contains(line), "{line} missing");
            }
        }
    }

    #[test]
    fn flags_override_the_file() {
        let mut s = Settings::from_toml(
            "[vehicle]\nid = \"a\"\n[zenoh]\nconnect = [\"tcp/1.2.3.4:7447\"]\n",
        )
        .expect("parses");
        s.apply(&SettingsFlags {
            vehicle: Some("b".into()),
            origin: Some(parse_origin("49.0,8.4,-1.5").expect("origin")),
            connect: vec!["tcp/127.0.0.1:7000".into()],
            ..Default::default()
        });
        assert_eq!(s.vehicle.id, "b");
        assert_eq!(s.fleet.origin, Some([49.0, 8.4, -1.5]));
        assert_eq!(s.zenoh.connect, ["tcp/127.0.0.1:7000"]);
        s.check().expect("valid");
    }

    #[test]
    fn unknown_keys_and_bad_values_are_refused() {
        assert!(Settings::from_toml("[http]\nlisten_on = \"x\"\n").is_err());
        let mut s = Settings::default();
        s.vehicle.id = "a/b".into();
        assert!(s.check().is_err());
        assert!(parse_origin("1,2").is_err());
    }

    #[test]
    fn default_imu_to_velo_is_kittis() {
        let t = VehicleSettings::default().imu_to_velo();
        assert!((t.translation.vector.x + 0.8086759).abs() < 1e-9);
        assert!(t.rotation.angle() < 0.02);
    }
}
