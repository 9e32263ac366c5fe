#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]
use skeleton_avoidance::{scenario, world::World};
fn main() {
    let name = std::env::args().nth(1).unwrap_or("dual-arm-self".into());
    let s = scenario::example(&name).unwrap();
    let robot = s.build_robot().unwrap();
    let mut w = World::new(s.clone()).unwrap();
    let dt = s.dt;
    let mut prev_q = w.q().to_vec();
    let mut prev_v = vec![0.0; prev_q.len()];
    for k in 0..((s.duration / dt) as usize) {
        w.step(dt);
        let q = w.q().to_vec();
        let v: Vec<f64> = q.iter().zip(&prev_q).map(|(a, b)| (a - b) / dt).collect();
        for i in 0..q.len() {
            let a = (v[i] - prev_v[i]) / dt;
            if a.abs() > robot.joints[i].max_acceleration * 1.001 {
                println!(
                    "step {k} t {:.3} joint {i} q {:.5} v {:.4} acc {:.1} lim {} qdot_state {:.4} min {:.4} max {:.4} stopped {}",
                    w.time(),
                    q[i],
                    v[i],
                    a,
                    robot.joints[i].max_acceleration,
                    w.motion().qdot[i],
                    robot.joints[i].min,
                    robot.joints[i].max,
                    w.is_stopped()
                );
            }
        }
        prev_q = q;
        prev_v = v;
    }
    for e in w.events().iter().take(30) {
        println!("{:.3} {:?}", e.t, e.kind);
    }
}
