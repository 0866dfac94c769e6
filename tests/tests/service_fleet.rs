//! Fleet behaviour of `trackd serve` on loopback: a Zenoh router, services and hand-built
//! super frames from other vehicles (explicit tcp/127.0.0.1 endpoints, free ports,
//! multicast scouting off).

use std::{
    future::Future,
    sync::atomic::{AtomicU64, Ordering},
    time::{Duration, Instant},
};

use prost::Message;
use trackd_client::{Client, api};
use trackd_proto::{Box3, GeoPoint, ObjectClass, SuperFrame, TrackedObject};
use trackd_service::{
    local_fleet::{LocalFleet, free_port, loopback_endpoint, loopback_settings},
    service::{self, alive_key, superframe_key},
    settings::{Settings, zenoh_config},
};
use zenoh::qos::CongestionControl;

const ORIGIN: [f64; 3] = [49.011_213_954_206, 8.422_885_922_889_3, 112.83];

fn base_settings() -> Settings {
    let mut s = Settings::default();
    s.fleet.origin = Some(ORIGIN);
    s.fleet.ttl_ms = 1_000;
    s.zenoh.max_message_bytes = 64 * 1024;
    s
}

/// Polls `probe` every 5 ms until it yields a value or `timeout` passes.
async fn wait_for<T, F, Fut>(timeout: Duration, mut probe: F) -> Option<(T, Duration)>
where
    F: FnMut() -> Fut,
    Fut: Future<Output = Option<T>>,
{
    let start = Instant::now();
    while start.elapsed() < timeout {
        if let Some(v) = probe().await {
            return Some((v, start.elapsed()));
        }
        tokio::time::sleep(Duration::from_millis(5)).await;
    }
    None
}

/// Another vehicle as the fleet sees it: a Zenoh peer with a liveliness token, publishing
/// hand-built super frames.
struct FakeVehicle {
    id: String,
    session: zenoh::Session,
    token: zenoh::liveliness::LivelinessToken,
    sequence: AtomicU64,
}

impl FakeVehicle {
    async fn join(id: &str, router_port: u16) -> Self {
        let config = zenoh_config(
            "peer",
            &[loopback_endpoint(free_port().expect("port"))],
            &[loopback_endpoint(router_port)],
            false,
        )
        .expect("config");
        let session = zenoh::open(config).await.expect("session");
        let token = session
            .liveliness()
            .declare_token(alive_key(id))
            .await
            .expect("token");
        Self {
            id: id.into(),
            session,
            token,
            sequence: AtomicU64::new(0),
        }
    }

    fn frame(&self, objects: &[(u64, f64, f64)]) -> SuperFrame {
        let sequence = self.sequence.fetch_add(1, Ordering::Relaxed) + 1;
        SuperFrame {
            version: trackd_proto::SCHEMA_VERSION,
            vehicle_id: self.id.clone(),
            sequence,
            timestamp: sequence as f64 * 0.1,
            ego_pose: None,
            origin: Some(GeoPoint {
                lat: ORIGIN[0],
                lon: ORIGIN[1],
                alt: ORIGIN[2],
            }),
            objects: objects
                .iter()
                .map(|&(id, x, y)| TrackedObject {
                    id,
                    class: ObjectClass::Car as i32,
                    r#box: Some(Box3 {
                        x,
                        y,
                        z: 0.8,
                        l: 4.2,
                        w: 1.8,
                        h: 1.5,
                        yaw: 0.3,
                    }),
                    confidence: 0.8,
                    ..Default::default()
                })
                .collect(),
        }
    }

    async fn publish(&self, objects: &[(u64, f64, f64)]) {
        let frame = self.frame(objects);
        self.session
            .put(superframe_key(&self.id), frame.encode_to_vec())
            .await
            .expect("put");
    }

    async fn leave(self) {
        self.token.undeclare().await.expect("undeclare");
        self.session.close().await.expect("close");
    }
}

fn with_source<'a>(objects: &'a api::FusedObjects, source: &str) -> Vec<&'a api::FusedObject> {
    objects
        .objects
        .iter()
        .filter(|o| o.sources.iter().any(|s| s == source))
        .collect()
}

async fn objects(a: &Client) -> api::FusedObjects {
    a.objects().await.expect("objects")
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn remote_objects_appear_fuse_expire_and_rejoin() {
    let fleet = LocalFleet::start(&["a".into()], &base_settings())
        .await
        .expect("fleet");
    let a = Client::new(&fleet.services[0].url(), None);
    let b = FakeVehicle::join("b", fleet.router_port).await;
    let c = FakeVehicle::join("c", fleet.router_port).await;

    // Liveliness reaches A through the router.
    let alive = wait_for(Duration::from_secs(10), || async {
        let f = a.fleet().await.ok()?;
        let ids: Vec<_> = f
            .vehicles
            .iter()
            .filter(|v| v.alive)
            .map(|v| v.id.clone())
            .collect();
        (ids == ["b", "c"]).then_some(())
    })
    .await;
    assert!(alive.is_some(), "A never saw b and c alive");

    // Warm up until a frame from each gets through (routes are set up lazily).
    for v in [&b, &c] {
        let id = v.id.clone();
        let seen = wait_for(Duration::from_secs(10), || {
            let fut = v.publish(&[(900, -50.0, -50.0)]);
            let a = &a;
            let id = id.clone();
            async move {
                fut.await;
                tokio::time::sleep(Duration::from_millis(20)).await;
                (!with_source(&objects(a).await, &id).is_empty()).then_some(())
            }
        })
        .await;
        assert!(seen.is_some(), "no super frame from {id} reached A");
    }

    // An object A cannot see (it has no tracks of its own here) and b sees: in A's view
    // within 200 ms, with b as its source.
    let sent = Instant::now();
    b.publish(&[(1, 30.0, 5.0)]).await;
    let (object, _) = wait_for(Duration::from_secs(2), || async {
        objects(&a)
            .await
            .objects
            .into_iter()
            .find(|o| o.id == "b/1")
    })
    .await
    .expect("b's object in A's view");
    let latency = sent.elapsed();
    assert!(latency < Duration::from_millis(200), "took {latency:?}");
    assert_eq!(object.sources, ["b"]);
    assert!((object.x - 30.0).abs() < 1e-6 && (object.y - 5.0).abs() < 1e-6);
    assert_eq!(object.class, "car");
    assert!((object.l - 4.2).abs() < 1e-9);

    // c sees the same car (0.4 m off) and another one: one fused car with two sources.
    c.publish(&[(7, 30.4, 5.1), (8, 60.0, -4.0)]).await;
    let (view, _) = wait_for(Duration::from_secs(2), || async {
        let v = objects(&a).await;
        (with_source(&v, "c").len() == 2).then_some(v)
    })
    .await
    .expect("c's objects in A's view");
    assert_eq!(view.objects.len(), 2, "{view:?}");
    let shared = view
        .objects
        .iter()
        .find(|o| o.id == "b/1")
        .expect("shared car");
    assert_eq!(shared.sources, ["b", "c"]);
    assert!(
        (shared.x - 30.2).abs() < 1e-6,
        "confidence-weighted mean, got {}",
        shared.x
    );
    assert!((shared.confidence - 0.96).abs() < 1e-5);
    let only_c = view
        .objects
        .iter()
        .find(|o| o.id == "c/8")
        .expect("c's car");
    assert_eq!(only_c.sources, ["c"]);

    // b leaves: its liveliness ends and what only it saw is gone at once.
    b.leave().await;
    let gone = wait_for(Duration::from_secs(5), || async {
        let v = objects(&a).await;
        with_source(&v, "b").is_empty().then_some(v)
    })
    .await;
    let (view, _) = gone.expect("b's objects expire when it leaves");
    assert_eq!(view.objects.len(), 2);
    let fleet_view = a.fleet().await.expect("fleet");
    let b_status = fleet_view
        .vehicles
        .iter()
        .find(|v| v.id == "b")
        .expect("b listed");
    assert!(!b_status.alive);

    // b comes back and is heard again.
    let b = FakeVehicle::join("b", fleet.router_port).await;
    let back = wait_for(Duration::from_secs(10), || {
        let fut = b.publish(&[(1, 31.0, 5.0)]);
        let a = &a;
        async move {
            fut.await;
            tokio::time::sleep(Duration::from_millis(20)).await;
            let v = objects(a).await;
            v.objects
                .iter()
                .any(|o| o.sources == ["b", "c"] || o.sources == ["c", "b"])
                .then_some(())
        }
    })
    .await;
    assert!(back.is_some(), "b did not rejoin");

    // c publishes once more, then falls silent but stays alive: its objects expire after
    // the TTL (1 s), not before.
    let silent_from = Instant::now();
    c.publish(&[(7, 30.4, 5.1), (8, 60.0, -4.0)]).await;
    let (_, _) = wait_for(Duration::from_secs(5), || async {
        with_source(&objects(&a).await, "c")
            .is_empty()
            .then_some(())
    })
    .await
    .expect("c's objects expire after the TTL");
    let silence = silent_from.elapsed();
    assert!(
        silence >= Duration::from_millis(950),
        "expired after {silence:?}"
    );
    let fleet_view = a.fleet().await.expect("fleet");
    let c_status = fleet_view
        .vehicles
        .iter()
        .find(|v| v.id == "c")
        .expect("c listed");
    assert!(c_status.alive);
    assert_eq!(c_status.objects, 0);

    b.leave().await;
    c.leave().await;
    fleet.stop().await.expect("stop");
}

/// Reads one counter of a Prometheus text exposition (0 when absent).
fn counter(metrics: &str, name_and_labels: &str) -> f64 {
    metrics
        .lines()
        .find_map(|l| l.strip_prefix(name_and_labels)?.trim().parse().ok())
        .unwrap_or(0.0)
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn rogue_zenoh_payloads_are_counted_and_change_nothing() {
    let fleet = LocalFleet::start(&["a".into()], &base_settings())
        .await
        .expect("fleet");
    let a = Client::new(&fleet.services[0].url(), None);
    let evil = FakeVehicle::join("evil", fleet.router_port).await;
    // Routes first: a valid frame must get through.
    let through = wait_for(Duration::from_secs(10), || {
        let fut = evil.publish(&[(1, 5.0, 5.0)]);
        let a = &a;
        async move {
            fut.await;
            tokio::time::sleep(Duration::from_millis(20)).await;
            (!with_source(&objects(a).await, "evil").is_empty()).then_some(())
        }
    })
    .await;
    assert!(through.is_some());

    let key = superframe_key("evil");
    // Blocking, not dropping, when a queue is full: on a loaded machine a burst of puts (one
    // of them fragmented) may otherwise lose one before the service sees it.
    let put = |bytes: Vec<u8>| {
        evil.session
            .put(key.clone(), bytes)
            .congestion_control(CongestionControl::Block)
    };
    put(b"\x0f\x00 not protobuf".to_vec()).await.expect("put");
    put(vec![0u8; 100 * 1024]).await.expect("put"); // over the 64 KiB limit
    let mut mismatch = evil.frame(&[(2, 1.0, 1.0)]);
    mismatch.vehicle_id = "someone-else".into();
    put(mismatch.encode_to_vec()).await.expect("put");
    let mut nan = evil.frame(&[(3, 1.0, 1.0)]);
    if let Some(b) = nan.objects[0].r#box.as_mut() {
        b.x = f64::NAN;
    }
    put(nan.encode_to_vec()).await.expect("put");
    let mut far = evil.frame(&[(4, 1.0, 1.0)]);
    far.origin = Some(GeoPoint {
        lat: -33.9,
        lon: 151.2,
        alt: 5.0,
    });
    put(far.encode_to_vec()).await.expect("put");
    let mut no_version = evil.frame(&[(5, 1.0, 1.0)]);
    no_version.version = 0;
    put(no_version.encode_to_vec()).await.expect("put");

    let expected = [
        ("decode", 1.0),
        ("oversized", 1.0),
        ("key_mismatch", 1.0),
        ("bad_object", 1.0),
        ("origin_too_far", 1.0),
        ("no_version", 1.0),
    ];
    let counted = wait_for(Duration::from_secs(10), || async {
        let m = a.metrics().await.ok()?;
        expected
            .iter()
            .all(|(reason, n)| {
                counter(
                    &m,
                    &format!("trackd_zenoh_rejected_total{{reason=\"{reason}\"}}"),
                ) == *n
            })
            .then_some(m)
    })
    .await;
    let (metrics, _) = match counted {
        Some(counted) => counted,
        None => {
            let m = a.metrics().await.unwrap_or_default();
            let seen: Vec<_> = m.lines().filter(|l| l.contains("rejected")).collect();
            panic!("rejections not all counted: {seen:?}");
        }
    };
    assert!(counter(&metrics, "trackd_zenoh_messages_total{direction=\"in\"}") >= 1.0);

    // Nothing of the rogue frames entered the view; the service still serves and ingests.
    let view = objects(&a).await;
    let ids: Vec<_> = view.objects.iter().map(|o| o.id.as_str()).collect();
    assert_eq!(ids, ["evil/1"]);
    evil.publish(&[(9, 7.0, 7.0)]).await;
    let ingested = wait_for(Duration::from_secs(2), || async {
        objects(&a)
            .await
            .objects
            .iter()
            .any(|o| o.id == "evil/9")
            .then_some(())
    })
    .await;
    assert!(ingested.is_some());
    assert_eq!(a.health().await.expect("health").status, "ok");

    evil.leave().await;
    fleet.stop().await.expect("stop");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn services_see_each_other_leave_and_rejoin() {
    let base = base_settings();
    let mut fleet = LocalFleet::start(&["a".into(), "b".into(), "c".into()], &base)
        .await
        .expect("fleet");
    let a = Client::new(&fleet.services[0].url(), None);
    let alive_set = |f: &api::Fleet| -> Vec<String> {
        f.vehicles
            .iter()
            .filter(|v| v.alive)
            .map(|v| v.id.clone())
            .collect()
    };
    let all = wait_for(Duration::from_secs(10), || async {
        (alive_set(&a.fleet().await.ok()?) == ["b", "c"]).then_some(())
    })
    .await;
    assert!(all.is_some(), "a never saw b and c");

    // Stop b: a sees it leave.
    let b = fleet.services.remove(1);
    b.stop().await.expect("stop b");
    let left = wait_for(Duration::from_secs(10), || async {
        (alive_set(&a.fleet().await.ok()?) == ["c"]).then_some(())
    })
    .await;
    assert!(left.is_some(), "a did not see b leave");

    // Restart b (new ports, same id): it rejoins.
    let b = service::start(loopback_settings("b", fleet.router_port, &base).expect("settings"))
        .await
        .expect("restart b");
    let back = wait_for(Duration::from_secs(10), || async {
        (alive_set(&a.fleet().await.ok()?) == ["b", "c"]).then_some(())
    })
    .await;
    assert!(back.is_some(), "b did not rejoin");
    // And b sees the others.
    let b_client = Client::new(&b.url(), None);
    let sees = wait_for(Duration::from_secs(10), || async {
        (alive_set(&b_client.fleet().await.ok()?) == ["a", "c"]).then_some(())
    })
    .await;
    assert!(sees.is_some(), "restarted b does not see a and c");
    b.stop().await.expect("stop b");
    fleet.stop().await.expect("stop");
}
