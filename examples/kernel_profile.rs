//! The fibre–fibre kernel on one pose of `benches/kernels.rs`, many times:
//! a deterministic workload for instruction counts (the machine is shared,
//! wall clocks are not). Usage:
//!
//! ```sh
//! cargo build --release --example kernel_profile
//! valgrind --tool=callgrind --callgrind-out-file=/tmp/cg target/release/examples/kernel_profile end/rim_on_side 10000
//! ```
//!
//! prints the pose's contacts and counters; the instructions per call are
//! callgrind's total over the count (the set-up is ~1e5 instructions).
//! Without arguments it lists the poses.

#[path = "../benches/common/poses.rs"]
mod poses;

use fibresim::contact::{contact_fibre_fibre, KernelCounters};
use std::hint::black_box;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let poses = poses::poses();
    let Some(name) = args.get(1) else {
        for (name, _, _) in &poses {
            println!("{name}");
        }
        return;
    };
    let count: u64 = args.get(2).map_or(10_000, |c| c.parse().expect("a count"));
    let Some((_, a, b)) = poses.iter().find(|p| p.0 == name) else {
        eprintln!("no pose {name}; run without arguments for the list");
        std::process::exit(2);
    };
    let (mut out, mut k) = (Vec::with_capacity(8), KernelCounters::default());
    for _ in 0..count {
        out.clear();
        contact_fibre_fibre(black_box(a), black_box(b), &mut out, &mut k);
        black_box(out.len());
    }
    println!(
        "{name}: {} contact point(s) per call, counters over {count} calls: {k:?}",
        out.len()
    );
}
