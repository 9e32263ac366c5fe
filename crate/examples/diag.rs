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
                println!("step {k} t {:.3} joint {i} q {:.5} v {:.4} acc {:.1} lim {} qdot_state {:.4} min {:.4} max {:.4} stopped {}", w.time(), q[i], v[i], a, robot.joints[i].max_acceleration, w.motion().qdot[i], robot.joints[i].min, robot.joints[i].max, w.is_stopped());
            }
        }
        let st = w.state();
        if let Some(c) = st.min_clearance { if c < 0.03 && k % 5 == 0 { println!("t {:.3} clearance {:.4} maxv {:.3} pts {:?}", w.time(), c, v.iter().fold(0.0f64, |m, x| m.max(x.abs())), st.control_points.iter().map(|p| (p.obstacle.clone(), (p.distance*1000.0).round())).collect::<Vec<_>>()); } }
        if w.time() > 0.6 && w.time() < 0.67 && k % 5 == 0 {
            for g in w.guards().iter().filter(|g| g.distance < 0.03) {
                let rv: f64 = g.row.iter().zip(&v).map(|(a, b)| a * b).sum();
                println!("   guard seg {} d {:.4} bound {:.4} row·v {:.4} row·qdot {:.4}", g.segment, g.distance, g.bound, rv, g.row.iter().zip(&w.motion().qdot).map(|(a, b)| a * b).sum::<f64>());
            }
        }
        prev_q = q; prev_v = v;
    }
    for e in w.events().iter().take(30) { println!("{:.3} {:?}", e.t, e.kind); }
}
