//! Human-readable tables.

use trackd_client::api;

fn or_dash<T: std::fmt::Display>(v: Option<T>) -> String {
    v.map_or_else(|| "-".to_string(), |v| v.to_string())
}

/// Tracks of a frame.
pub fn tracks(t: &api::Tracks) {
    println!(
        "vehicle {}  frame {}  t {}  ({} frame, {} tracks)",
        t.vehicle,
        or_dash(t.frame),
        or_dash(t.timestamp.map(|s| format!("{s:.3}"))),
        t.tracking_frame.as_deref().unwrap_or("-"),
        t.tracks.len()
    );
    println!(
        "{:>6}  {:<13} {:>9} {:>9} {:>6}  {:>5} {:>5} {:>5}  {:>6} {:>6}  {:>5}",
        "id", "class", "x", "y", "z", "l", "w", "h", "vx", "vy", "conf"
    );
    for k in &t.tracks {
        println!(
            "{:>6}  {:<13} {:>9.2} {:>9.2} {:>6.2}  {:>5.2} {:>5.2} {:>5.2}  {:>6.2} {:>6.2}  {:>5.2}",
            k.id, k.class, k.x, k.y, k.z, k.l, k.w, k.h, k.vx, k.vy, k.confidence
        );
    }
}

/// One track with its history.
pub fn track(t: &api::TrackHistory) {
    match &t.current {
        Some(c) => println!(
            "track {}: {} at ({:.2}, {:.2}, {:.2}), confidence {:.2}, {} hits in {} frames",
            t.id, c.class, c.x, c.y, c.z, c.confidence, c.hits, c.age
        ),
        None => println!("track {}: no longer tracked", t.id),
    }
    println!(
        "{:>8} {:>12} {:>9} {:>9} {:>7}",
        "frame", "t", "x", "y", "z"
    );
    for p in &t.history {
        println!(
            "{:>8} {:>12.3} {:>9.2} {:>9.2} {:>7.2}",
            p.frame, p.timestamp, p.x, p.y, p.z
        );
    }
}

/// The fleet.
pub fn fleet(f: &api::Fleet) {
    println!(
        "vehicle {}  origin {}",
        f.vehicle,
        f.origin.map_or("-".into(), |o| format!(
            "{:.7}, {:.7}, {:.2}",
            o[0], o[1], o[2]
        ))
    );
    println!(
        "{:<16} {:>5} {:>10} {:>8} {:>8} {:>8} {:>7}",
        "vehicle", "alive", "last seen", "lag ms", "seq", "objects", "frames"
    );
    for v in &f.vehicles {
        println!(
            "{:<16} {:>5} {:>10} {:>8} {:>8} {:>8} {:>7}",
            v.id,
            if v.alive { "yes" } else { "no" },
            or_dash(v.last_seen_ms.map(|ms| format!("{ms} ms"))),
            or_dash(v.lag_ms.map(|l| format!("{l:.1}"))),
            or_dash(v.sequence),
            v.objects,
            v.superframes
        );
    }
}

/// The fused view.
pub fn objects(o: &api::FusedObjects) {
    println!(
        "{:<20} {:<13} {:>9} {:>9} {:>6}  {:>5}  {:>7}  sources",
        "id", "class", "x", "y", "z", "conf", "age ms"
    );
    for k in &o.objects {
        println!(
            "{:<20} {:<13} {:>9.2} {:>9.2} {:>6.2}  {:>5.2}  {:>7}  {}",
            k.id,
            k.class,
            k.x,
            k.y,
            k.z,
            k.confidence,
            k.age_ms,
            k.sources.join(",")
        );
    }
}
