//! A client for trackd's REST API.
//!
//! ```no_run
//! # async fn demo() -> Result<(), trackd_client::ClientError> {
//! let client = trackd_client::Client::new("http://127.0.0.1:8080", None);
//! for track in client.tracks().await?.tracks {
//!     println!("{} {} at ({:.1}, {:.1})", track.id, track.class, track.x, track.y);
//! }
//! # Ok(()) }
//! ```

#![warn(missing_docs)]

pub mod api;
mod error;
pub mod sse;

pub use error::ClientError;

use prost::Message;
use reqwest::{StatusCode, header};
use serde::de::DeserializeOwned;

/// A connection to one trackd service.
#[derive(Clone)]
pub struct Client {
    base: String,
    token: Option<String>,
    http: reqwest::Client,
}

/// A raw scan body and how the service should read it.
pub enum ScanBody {
    /// A protobuf `trackd_proto::Scan` (carries its own timestamp and pose or OXTS).
    Protobuf(trackd_proto::Scan),
    /// A KITTI `.bin` or PCD file's bytes, with what the file itself does not say.
    Raw {
        /// The bytes of the file.
        bytes: Vec<u8>,
        /// [`api::KITTI_BIN`] or [`api::PCD`].
        content_type: &'static str,
        /// Scan timestamp (seconds).
        timestamp: f64,
        /// Pose `x,y,z,qw,qx,qy,qz` of the sensor in the world frame, if known.
        pose: Option<[f64; 7]>,
        /// The OXTS packet's 30 values, if known.
        oxts: Option<Vec<f64>>,
    },
}

/// What an upload led to.
#[derive(Clone, Debug, PartialEq)]
pub enum Uploaded {
    /// Processed: the frame and the tracks after it.
    Processed(api::ScanProcessed),
    /// Queued (`async`): its id and the queue depth.
    Queued(api::ScanQueued),
}

fn join(values: impl IntoIterator<Item = f64>) -> String {
    values
        .into_iter()
        .map(|v| v.to_string())
        .collect::<Vec<_>>()
        .join(",")
}

impl Client {
    /// A client of the service at `base` (e.g. `http://127.0.0.1:8080`), sending `token` as a
    /// bearer token on writes when given.
    pub fn new(base: &str, token: Option<String>) -> Self {
        Self {
            base: base.trim_end_matches('/').to_string(),
            token,
            http: reqwest::Client::new(),
        }
    }

    /// The service's base URL.
    pub fn base(&self) -> &str {
        &self.base
    }

    fn url(&self, path: &str) -> String {
        format!("{}{}", self.base, path)
    }

    async fn send(
        &self,
        url: &str,
        request: reqwest::RequestBuilder,
    ) -> Result<reqwest::Response, ClientError> {
        let response = request
            .send()
            .await
            .map_err(|source| ClientError::Transport {
                url: url.to_string(),
                source,
            })?;
        let status = response.status();
        if status.is_success() {
            return Ok(response);
        }
        if status == StatusCode::TOO_MANY_REQUESTS {
            let retry_after_s = response
                .headers()
                .get(header::RETRY_AFTER)
                .and_then(|v| v.to_str().ok())
                .and_then(|v| v.parse().ok())
                .unwrap_or(1);
            return Err(ClientError::Busy { retry_after_s });
        }
        let body = response.text().await.unwrap_or_default();
        let message = serde_json::from_str::<api::ApiError>(&body)
            .map(|e| e.error)
            .unwrap_or(body);
        Err(ClientError::Status {
            url: url.to_string(),
            status: status.as_u16(),
            message,
        })
    }

    async fn get_json<T: DeserializeOwned>(&self, path: &str) -> Result<T, ClientError> {
        let url = self.url(path);
        let response = self.send(&url, self.http.get(&url)).await?;
        let bytes = response
            .bytes()
            .await
            .map_err(|source| ClientError::Transport {
                url: url.clone(),
                source,
            })?;
        serde_json::from_slice(&bytes).map_err(|e| ClientError::Decode {
            url,
            message: e.to_string(),
        })
    }

    async fn get_bytes(&self, path: &str, accept: &str) -> Result<Vec<u8>, ClientError> {
        let url = self.url(path);
        let response = self
            .send(&url, self.http.get(&url).header(header::ACCEPT, accept))
            .await?;
        let bytes = response
            .bytes()
            .await
            .map_err(|source| ClientError::Transport { url, source })?;
        Ok(bytes.to_vec())
    }

    /// Uploads one scan; with `queue_only` the service answers as soon as it is queued.
    pub async fn upload(&self, scan: ScanBody, queue_only: bool) -> Result<Uploaded, ClientError> {
        let url = self.url("/v1/scans");
        let mut request = self.http.post(&url);
        if queue_only {
            request = request.query(&[("async", "true")]);
        }
        if let Some(token) = &self.token {
            request = request.bearer_auth(token);
        }
        request = match scan {
            ScanBody::Protobuf(scan) => request
                .header(header::CONTENT_TYPE, api::PROTOBUF)
                .body(scan.encode_to_vec()),
            ScanBody::Raw {
                bytes,
                content_type,
                timestamp,
                pose,
                oxts,
            } => {
                let mut r = request
                    .header(header::CONTENT_TYPE, content_type)
                    .header(api::HEADER_TIMESTAMP, timestamp.to_string());
                if let Some(pose) = pose {
                    r = r.header(api::HEADER_POSE, join(pose));
                }
                if let Some(oxts) = oxts {
                    r = r.header(api::HEADER_OXTS, join(oxts));
                }
                r.body(bytes)
            }
        };
        let response = self.send(&url, request).await?;
        let status = response.status();
        let bytes = response
            .bytes()
            .await
            .map_err(|source| ClientError::Transport {
                url: url.clone(),
                source,
            })?;
        let decode = |e: serde_json::Error| ClientError::Decode {
            url: url.clone(),
            message: e.to_string(),
        };
        if status == StatusCode::ACCEPTED {
            Ok(Uploaded::Queued(
                serde_json::from_slice(&bytes).map_err(decode)?,
            ))
        } else {
            Ok(Uploaded::Processed(
                serde_json::from_slice(&bytes).map_err(decode)?,
            ))
        }
    }

    /// `GET /v1/tracks`: the tracks after the latest frame.
    pub async fn tracks(&self) -> Result<api::Tracks, ClientError> {
        self.get_json("/v1/tracks").await
    }

    /// `GET /v1/tracks/{id}`: one track and its history.
    pub async fn track(&self, id: u64) -> Result<api::TrackHistory, ClientError> {
        self.get_json(&format!("/v1/tracks/{id}")).await
    }

    /// `GET /v1/fleet`: the vehicles this service knows of.
    pub async fn fleet(&self) -> Result<api::Fleet, ClientError> {
        self.get_json("/v1/fleet").await
    }

    /// `GET /v1/fleet/objects`: the fused world view.
    pub async fn objects(&self) -> Result<api::FusedObjects, ClientError> {
        self.get_json("/v1/fleet/objects").await
    }

    /// `GET /v1/superframes/latest` as protobuf.
    pub async fn latest_superframe(&self) -> Result<trackd_proto::SuperFrame, ClientError> {
        let url = self.url("/v1/superframes/latest");
        let bytes = self
            .get_bytes("/v1/superframes/latest", api::PROTOBUF)
            .await?;
        trackd_proto::SuperFrame::decode(bytes.as_slice()).map_err(|e| ClientError::Decode {
            url,
            message: e.to_string(),
        })
    }

    /// `GET /v1/occupancy`: the occupancy map as an OctoMap `.bt` file.
    pub async fn occupancy_bt(&self) -> Result<Vec<u8>, ClientError> {
        self.get_bytes("/v1/occupancy", api::OCTOMAP_BT).await
    }

    /// `GET /healthz`.
    pub async fn health(&self) -> Result<api::Health, ClientError> {
        self.get_json("/healthz").await
    }

    /// `GET /metrics`: Prometheus text.
    pub async fn metrics(&self) -> Result<String, ClientError> {
        let bytes = self.get_bytes("/metrics", "text/plain").await?;
        Ok(String::from_utf8_lossy(&bytes).into_owned())
    }

    /// `GET /v1/stream`: calls `on_tracks` with each frame's tracks until it returns false or
    /// the stream ends.
    pub async fn watch(
        &self,
        mut on_tracks: impl FnMut(api::Tracks) -> bool,
    ) -> Result<(), ClientError> {
        let url = self.url("/v1/stream");
        let mut response = self
            .send(
                &url,
                self.http
                    .get(&url)
                    .header(header::ACCEPT, "text/event-stream"),
            )
            .await?;
        let mut parser = sse::SseParser::default();
        loop {
            let chunk = response
                .chunk()
                .await
                .map_err(|source| ClientError::Transport {
                    url: url.clone(),
                    source,
                })?;
            let Some(chunk) = chunk else { return Ok(()) };
            for event in parser.feed(&chunk) {
                if event.event != "tracks" {
                    continue;
                }
                let tracks =
                    serde_json::from_str(&event.data).map_err(|e| ClientError::Decode {
                        url: url.clone(),
                        message: e.to_string(),
                    })?;
                if !on_tracks(tracks) {
                    return Ok(());
                }
            }
        }
    }
}
