//! The spectra against GetFEM on the same meshes, when it is installed.

use super::plates::{omega_squared, scene, CLAMPS};
use plate_impact::element::ElementKind;
use std::process::Command;

/// GetFEM (Debian package python3-getfem, run by /usr/bin/python3) on the same meshes: its own
/// Argyris and reduced FVS elements, quadrature and assembly, the clamp as the kernel of a
/// boundary form (`getfem_spectrum.py`). The two solve the same discrete eigenproblem (the same
/// spaces, both integrated exactly), so ω₁² … ω₆² must agree to round-off: the reduction through
/// K loses about ε ω_max²/ω_k² ≲ 1e-10 relative on these meshes (tests/modes.rs measures that
/// between two implementations of its own), and GetFEM's kernel basis adds the eigensolver's
/// round-off of the boundary form (measured: 3.0e-10 at most, λ₁ of Argyris "xmin, ymin"; 7.6e-9
/// before the script scaled GetFEM's unscaled derivative dofs); 1e-8 relative is a margin over
/// both, while a clamp that fixed a dof too many or too few moves ω² by 1e-4 and more (the root
/// curvature fixed as well moves the cantilever's f₁ by 1.3 %, docs/elements.md §5). Skipped,
/// saying why, when GetFEM is absent.
#[test]
fn getfem_gives_the_same_spectra_on_the_same_meshes() {
    let script = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/general_model/getfem_spectrum.py"
    );
    let probe = Command::new("/usr/bin/python3")
        .args(["-c", "import getfem, numpy, scipy"])
        .output();
    match probe {
        Ok(out) if out.status.success() => {}
        Ok(out) => {
            let why = String::from_utf8_lossy(&out.stderr);
            let why = why.lines().last().unwrap_or("");
            println!("skipped: GetFEM does not import in /usr/bin/python3 ({why}); install the Debian package python3-getfem");
            return;
        }
        Err(e) => {
            println!("skipped: /usr/bin/python3 does not run ({e}), so GetFEM cannot");
            return;
        }
    }
    let mut worst = 0.0f64;
    // The three clamps, and a segment of one edge with a whole other edge: the segment's end
    // vertices keep their clamp dofs (the trace's second tangential derivative and the twist
    // vanish there too), which only the comparison of the spaces checks.
    let cases = CLAMPS
        .iter()
        .map(|c| (c.text, c.sides))
        .chain([("ymin(0.1, 0.3), xmax", &["ymin:0.1:0.3", "xmax"][..])]);
    for (text, sides) in cases {
        for (element, name, nx, ny) in [
            (ElementKind::Argyris, "argyris", 10, 7),
            (ElementKind::Fvs, "fvs", 14, 10),
        ] {
            let s = scene(text, element, nx, ny);
            let ours = omega_squared(&s);
            let number = |v: f64| format!("{v:e}");
            let out = Command::new("/usr/bin/python3")
                .arg(script)
                .args([name.to_string(), nx.to_string(), ny.to_string()])
                .args([
                    number(s.plate.length),
                    number(s.plate.width),
                    number(s.bending_stiffness()),
                    number(s.areal_mass()),
                    number(s.material.poisson_ratio),
                ])
                .arg("6")
                .args(sides)
                .output()
                .unwrap();
            assert!(
                out.status.success(),
                "{}",
                String::from_utf8_lossy(&out.stderr)
            );
            let theirs: Vec<f64> = String::from_utf8(out.stdout)
                .unwrap()
                .split_whitespace()
                .map(|v| v.parse().unwrap())
                .collect();
            assert_eq!(theirs.len(), 6);
            for k in 0..6 {
                let relative = (ours[k] - theirs[k]) / theirs[k];
                worst = worst.max(relative.abs());
                assert!(
                    relative.abs() <= 1e-8,
                    "{text} {element:?} mode {}: ω² {} here, {} in GetFEM ({relative:e})",
                    k + 1,
                    ours[k],
                    theirs[k]
                );
            }
        }
    }
    println!("GetFEM and PlateImpact agree on ω₁² … ω₆² to {worst:.1e} relative");
}
