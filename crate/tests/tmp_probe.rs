#![allow(clippy::unwrap_used)]
use skeleton_avoidance::scenario::{self, EXAMPLE_NAMES};
use skeleton_avoidance::world::simulate;
#[test]
fn probe() {
    for name in EXAMPLE_NAMES {
        let s = scenario::example(name).unwrap();
        let t = simulate(&s).unwrap();
        let mut counts = std::collections::BTreeMap::new();
        for e in &t.events {
            let k = format!("{:?}", e.kind);
            let k = k.split([' ', '{']).next().unwrap().to_string();
            *counts.entry(k).or_insert(0) += 1;
        }
        println!("{name}: {counts:?}");
    }
}
