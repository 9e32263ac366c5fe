fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(10);
    let steps: usize = std::env::args()
        .nth(2)
        .and_then(|s| s.parse().ok())
        .unwrap_or(4000);
    let start = skeleton_avoidance::world::control_step_workload(n).unwrap();
    let mut best = f64::INFINITY;
    for _ in 0..5 {
        let mut w = start.clone();
        let t = std::time::Instant::now();
        for _ in 0..steps {
            w.step(0.001);
        }
        best = best.min(t.elapsed().as_secs_f64() / steps as f64 * 1e6);
    }
    println!("N={n} best-of-5 mean {best:.1} us/step");
}
