fn main() {
    use cfe_tools::verification::segment::*;
    for k in [4usize, 8, 16] {
        for c in ["node", "segment"] {
            let e = cylinder_run(k, c).unwrap();
            let b = cantilever_run(k, c).unwrap();
            println!(
                "k {k} {c}: cyl {:.3e} {:.3e} {:.3e} | beam {:.3e} {:.3e} {:.3e}",
                e.displacement, e.energy, e.traction, b.displacement, b.energy, b.traction
            );
        }
    }
}
