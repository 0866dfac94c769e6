//! Time to simulate one scan (ray casting 64 × 2000 beams, labels, ground truth) per scenario.

use trackd_sim::{Scenario, SimConfig, Simulation};

fn main() {
    divan::main();
}

/// One frame of vehicle 0, mid-drive, in each scenario.
#[divan::bench(args = Scenario::ALL, sample_count = 10, sample_size = 1)]
fn frame(bencher: divan::Bencher, scenario: Scenario) {
    let sim = Simulation::new(&SimConfig::new(scenario, 40, 1)).expect("scenario builds");
    bencher.bench_local(|| sim.frame(0, divan::black_box(20)));
}

/// Building a world and every vehicle's motion and OXTS (no scans).
#[divan::bench(args = Scenario::ALL, sample_count = 5, sample_size = 1)]
fn world(scenario: Scenario) -> Simulation {
    Simulation::new(&SimConfig::new(scenario, 100, 1).with_vehicles(2)).expect("scenario builds")
}
