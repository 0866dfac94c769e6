//! The REST API of one `trackd serve` on loopback: uploads (good and bad), auth, tracks,
//! SSE, OpenAPI, health and metrics. Zenoh listens on an explicit tcp/127.0.0.1 port with
//! multicast scouting off and connects nowhere.

use std::{sync::Arc, time::Duration};

use prost::Message;
use reqwest::{StatusCode, header};
use trackd_client::{Client, ScanBody, Uploaded, api};
use trackd_service::{
    local_fleet::{free_port, loopback_endpoint},
    service::{self, RunningService},
    settings::Settings,
};

const TOKEN: &str = "s3cret";

/// A bad upload: content type, token, body, expected status, words the error must contain.
type BadUpload = (
    &'static str,
    Option<&'static str>,
    Vec<u8>,
    StatusCode,
    &'static str,
);

async fn start(max_body_bytes: usize) -> RunningService {
    start_with_queue(max_body_bytes, Settings::default().queue.capacity).await
}

async fn start_with_queue(max_body_bytes: usize, queue_capacity: usize) -> RunningService {
    let mut s = Settings::default();
    s.queue.capacity = queue_capacity;
    s.vehicle.id = "solo".into();
    s.http.listen = "127.0.0.1:0".parse().expect("addr");
    s.http.max_body_bytes = max_body_bytes;
    s.zenoh.listen = vec![loopback_endpoint(free_port().expect("port"))];
    s.zenoh.connect = Vec::new();
    s.auth.token = TOKEN.into();
    service::start(s).await.expect("service starts")
}

/// A KITTI `.bin` of `points` points: walls 2-22 m ahead, 2 m high, 0.5 m apart, on a
/// 0.1 m grid (work for every stage of the pipeline).
fn bin(points: usize) -> Vec<u8> {
    (0..points)
        .flat_map(|i| {
            let (x, z, wall) = (i % 200, (i / 200) % 20, i / 4000);
            [
                2.0 + x as f32 * 0.1,
                wall as f32 * 0.5 - 5.0,
                z as f32 * 0.1 - 1.7,
                0.5,
            ]
        })
        .flat_map(f32::to_le_bytes)
        .collect()
}

fn raw(timestamp: f64, points: usize) -> ScanBody {
    ScanBody::Raw {
        bytes: bin(points),
        content_type: api::KITTI_BIN,
        timestamp,
        pose: Some([0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0]),
        oxts: None,
    }
}

fn counter(metrics: &str, name_and_labels: &str) -> f64 {
    metrics
        .lines()
        .find_map(|l| l.strip_prefix(name_and_labels)?.trim().parse().ok())
        .unwrap_or(0.0)
}

async fn post(
    http: &reqwest::Client,
    url: &str,
    content_type: &str,
    token: Option<&str>,
    body: Vec<u8>,
) -> (StatusCode, String) {
    let mut r = http
        .post(format!("{url}/v1/scans?timestamp=100"))
        .header(header::CONTENT_TYPE, content_type)
        .body(body);
    if let Some(t) = token {
        r = r.bearer_auth(t);
    }
    let response = r.send().await.expect("request");
    let status = response.status();
    (status, response.text().await.expect("body"))
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn bad_uploads_get_the_right_4xx_and_the_service_goes_on() {
    let service = start(1024 * 1024).await;
    let url = service.url();
    let client = Client::new(&url, Some(TOKEN.into()));
    let http = reqwest::Client::new();

    // A good scan is processed: frame 0 with its point count.
    let Uploaded::Processed(first) = client.upload(raw(1.0, 100), false).await.expect("upload")
    else {
        panic!("synchronous upload answered 202")
    };
    assert_eq!((first.scan_id, first.frame, first.points), (0, 0, 100));
    assert_eq!(first.tracks.vehicle, "solo");

    let cases: [BadUpload; 6] = [
        (
            api::KITTI_BIN,
            None,
            bin(1),
            StatusCode::UNAUTHORIZED,
            "Bearer",
        ),
        (
            api::KITTI_BIN,
            Some("wrong"),
            bin(1),
            StatusCode::UNAUTHORIZED,
            "Bearer",
        ),
        (
            api::KITTI_BIN,
            Some(TOKEN),
            bin(3)[..40].to_vec(),
            StatusCode::BAD_REQUEST,
            "multiple of 16",
        ),
        (
            api::PROTOBUF,
            Some(TOKEN),
            b"\x0f\x00garbage".to_vec(),
            StatusCode::BAD_REQUEST,
            "protobuf",
        ),
        (
            "text/plain",
            Some(TOKEN),
            b"hello".to_vec(),
            StatusCode::UNSUPPORTED_MEDIA_TYPE,
            "content type",
        ),
        (
            api::KITTI_BIN,
            Some(TOKEN),
            bin(70_000),
            StatusCode::PAYLOAD_TOO_LARGE,
            "",
        ),
    ];
    for (content_type, token, body, status, says) in cases {
        let (got, text) = post(&http, &url, content_type, token, body).await;
        assert_eq!(got, status, "{content_type} {token:?}: {text}");
        let error: api::ApiError = serde_json::from_str(&text).expect("JSON error body");
        assert!(error.error.contains(says), "{} lacks {says:?}", error.error);
    }

    // A scan whose time goes backwards is refused by the pipeline (422), not lost silently.
    let backwards = client.upload(raw(0.5, 10), false).await;
    assert!(
        matches!(
            backwards,
            Err(trackd_client::ClientError::Status { status: 422, .. })
        ),
        "{backwards:?}"
    );

    // The service goes on: the next good scan is frame 1.
    let Uploaded::Processed(second) = client.upload(raw(2.0, 50), false).await.expect("upload")
    else {
        panic!("synchronous upload answered 202")
    };
    assert_eq!(second.frame, 1);

    let m = client.metrics().await.expect("metrics");
    assert_eq!(counter(&m, "trackd_frames_total"), 2.0);
    assert_eq!(
        counter(&m, "trackd_scans_rejected_total{reason=\"unauthorized\"}"),
        2.0
    );
    assert_eq!(
        counter(&m, "trackd_scans_rejected_total{reason=\"bad_request\"}"),
        2.0
    );
    assert_eq!(
        counter(
            &m,
            "trackd_scans_rejected_total{reason=\"unsupported_media_type\"}"
        ),
        1.0
    );
    assert_eq!(
        counter(&m, "trackd_scans_rejected_total{reason=\"too_large\"}"),
        1.0
    );
    assert_eq!(
        counter(&m, "trackd_drops_total{reason=\"pipeline_error\"}"),
        1.0
    );
    service.stop().await.expect("stop");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_flood_of_uploads_is_queued_or_refused_with_429_never_lost() {
    // A queue of 2 and 64 concurrent uploads of scans the worker needs milliseconds for:
    // the queue fills, so some uploads must be refused.
    let service = start_with_queue(16 * 1024 * 1024, 2).await;
    let client = Arc::new(Client::new(&service.url(), Some(TOKEN.into())));
    let mut tasks = Vec::new();
    for i in 0..64 {
        let client = client.clone();
        tasks.push(tokio::spawn(async move {
            client.upload(raw(1.0 + f64::from(i), 20_000), true).await
        }));
    }
    let mut queued = 0u64;
    let mut busy = 0u64;
    for t in tasks {
        match t.await.expect("task") {
            Ok(Uploaded::Queued(q)) => {
                assert!(q.queue_depth <= 2);
                queued += 1;
            }
            Err(trackd_client::ClientError::Busy { retry_after_s }) => {
                assert!(retry_after_s >= 1);
                busy += 1;
            }
            other => panic!("unexpected answer {other:?}"),
        }
    }
    assert_eq!(queued + busy, 64);
    assert!(busy > 0, "the full queue refused nothing");
    // Every queued scan becomes a frame or a counted pipeline refusal (timestamps of the
    // concurrent uploads may arrive out of order): none vanishes.
    let mut settled = false;
    for _ in 0..400 {
        let m = client.metrics().await.expect("metrics");
        let frames = counter(&m, "trackd_frames_total");
        let refused = counter(&m, "trackd_drops_total{reason=\"pipeline_error\"}");
        let rejected = counter(&m, "trackd_scans_rejected_total{reason=\"queue_full\"}");
        if frames + refused == queued as f64 {
            assert_eq!(rejected, busy as f64);
            settled = true;
            break;
        }
        tokio::time::sleep(Duration::from_millis(10)).await;
    }
    assert!(settled, "queued scans were lost");
    service.stop().await.expect("stop");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn reads_stream_and_documents_the_api() {
    let service = start(16 * 1024 * 1024).await;
    let url = service.url();
    let client = Client::new(&url, Some(TOKEN.into()));

    // Before any scan: empty tracks, healthy.
    let tracks = client.tracks().await.expect("tracks");
    assert_eq!((tracks.vehicle.as_str(), tracks.frame), ("solo", None));
    let health = client.health().await.expect("health");
    assert_eq!((health.frames, health.zenoh), (0, true));
    match client.track(42).await {
        Err(trackd_client::ClientError::Status { status: 404, .. }) => {}
        other => panic!("expected 404, got {other:?}"),
    }

    // SSE: a watcher gets the frame an upload makes.
    let watcher = {
        let client = client.clone();
        tokio::spawn(async move {
            let mut got = None;
            client
                .watch(|t| {
                    got = Some(t);
                    false
                })
                .await
                .map(|()| got)
        })
    };
    tokio::time::sleep(Duration::from_millis(200)).await;
    let scan = trackd_proto::Scan {
        version: trackd_proto::SCHEMA_VERSION,
        timestamp: 5.0,
        points: bin(10),
        ego: None,
    };
    let uploaded = client
        .upload(ScanBody::Protobuf(scan), false)
        .await
        .expect("upload");
    assert!(matches!(&uploaded, Uploaded::Processed(p) if p.frame == 0 && p.points == 10));
    let event = tokio::time::timeout(Duration::from_secs(5), watcher)
        .await
        .expect("event in time")
        .expect("task")
        .expect("stream")
        .expect("an event");
    assert_eq!(event.frame, Some(0));
    assert_eq!(event.timestamp, Some(5.0));
    assert_eq!(client.tracks().await.expect("tracks").frame, Some(0));
    assert_eq!(client.health().await.expect("health").frames, 1);

    // The occupancy map: an OctoMap .bt download and a BEV grid around the vehicle.
    let bt = client.occupancy_bt().await.expect("occupancy .bt");
    let header = String::from_utf8_lossy(&bt[..bt.len().min(200)]).into_owned();
    assert!(
        header.starts_with("# Octomap OcTree binary file") && header.contains("\nres 0.25\n"),
        "not an OctoMap .bt header: {header:?}"
    );
    let grid: api::BevGrid = reqwest::Client::new()
        .get(format!("{url}/v1/occupancy?format=grid&half_extent=20"))
        .send()
        .await
        .expect("request")
        .json()
        .await
        .expect("grid JSON");
    assert!(grid.width > 0 && grid.height > 0);
    assert_eq!(grid.cells.len(), grid.width * grid.height);

    // No super frame yet: 404 in both representations.
    let http = reqwest::Client::new();
    let r = http
        .get(format!("{url}/v1/superframes/latest"))
        .header(header::ACCEPT, api::PROTOBUF)
        .send()
        .await
        .expect("request");
    assert_eq!(r.status(), StatusCode::NOT_FOUND);

    // The OpenAPI document names every route and the bearer scheme.
    let doc: serde_json::Value = http
        .get(format!("{url}/openapi.json"))
        .send()
        .await
        .expect("request")
        .json()
        .await
        .expect("JSON");
    assert!(doc["openapi"].as_str().is_some_and(|v| v.starts_with("3.")));
    for path in [
        "/v1/scans",
        "/v1/tracks",
        "/v1/tracks/{id}",
        "/v1/superframes/latest",
        "/v1/fleet",
        "/v1/fleet/objects",
        "/v1/occupancy",
        "/v1/stream",
        "/healthz",
        "/metrics",
    ] {
        assert!(doc["paths"].get(path).is_some(), "{path} missing");
    }
    assert!(doc["components"]["securitySchemes"].get("bearer").is_some());
    assert!(
        doc["components"]["schemas"]["FusedObject"]["properties"]
            .get("sources")
            .is_some()
    );

    // The metrics expose per-stage latency, the queue and Zenoh counters.
    let m = client.metrics().await.expect("metrics");
    for family in [
        "trackd_frame_latency_ms",
        "trackd_queue_depth",
        "trackd_frames_total",
    ] {
        assert!(m.contains(family), "{family} missing");
    }
    // Protobuf round trip of the scan message kept its bytes.
    let _ = trackd_proto::Scan::decode(&[][..]).expect("empty message decodes");
    service.stop().await.expect("stop");
}
