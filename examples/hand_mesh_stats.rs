use prehensile::hand::*;
fn main() {
    for res in [0.5, 0.75, 1.0, 1.5] {
        let sk = Skeleton::new(Side::Right);
        let skin = SkinShape::new(Side::Right);
        let t = std::time::Instant::now();
        let f = mesh_flesh(&sk, &skin, res).unwrap();
        let el = t.elapsed();
        if res == 1.0 {
            write_obj("/tmp/hand.obj", &f);
        }
        let attached = f.node_bone.iter().filter(|b| b.is_some()).count();
        let mut worst = f64::INFINITY;
        for c in 0..f.mesh.cells.len() {
            worst = worst.min(prehensile::fem::hex8::scaled_jacobian(
                &f.mesh.cell_coords(c),
            ));
        }
        let (piece, pieces) = f.mesh.connected_pieces();
        let mut sizes = vec![0; pieces];
        for p in &piece {
            sizes[*p] += 1;
        }
        println!("res {res}: cells {} nodes {} attached {} free dofs {} skin quads {} worst SJ {worst:.3} pieces {sizes:?} time {el:?}",
            f.mesh.cells.len(), f.mesh.nodes.len(), attached, 3*(f.mesh.nodes.len()-attached), f.skin_quads.len());
        for (n, p) in piece.iter().enumerate() {
            if sizes[*p] < 50 {
                println!(
                    "  isolated node {n} at {:?} bone {:?}",
                    f.mesh.nodes[n].as_slice(),
                    f.node_bone[n]
                );
            }
        }
    }
}

#[allow(dead_code)]
pub fn write_obj(path: &str, f: &FleshMesh) {
    use std::io::Write;
    let mut s = std::fs::File::create(path).unwrap();
    for p in &f.mesh.nodes {
        writeln!(s, "v {} {} {}", p.x, p.y, p.z).unwrap();
    }
    for q in &f.skin_quads {
        writeln!(s, "f {} {} {} {}", q[0] + 1, q[1] + 1, q[2] + 1, q[3] + 1).unwrap();
    }
}
