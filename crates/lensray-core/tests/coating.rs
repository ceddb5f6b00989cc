//! Thin-film reflectance (`optics::coating`) against an independent transfer-matrix package:
//! tmm 0.2.0's reflectances of a quarter-wave MgF2 layer at 550 nm, and of the bare interface,
//! between five pairs of media (air and crown, air and dense flint, each way, and a cemented
//! pair), at five angles and five wavelengths, past the critical angle included
//! (`optics_reference/coating.tmm.json`, made by scripts/optics/coating_reference.py).

use lensray_core::optics::coating::{Coating, DESIGN_NM, MGF2_INDEX};

#[derive(serde::Deserialize)]
struct Case {
    n_from: f64,
    n_to: f64,
    degrees: f64,
    lambda_nm: f64,
    coated: f64,
    uncoated: f64,
}

#[derive(serde::Deserialize)]
struct Reference {
    layer_index: f64,
    design_nm: f64,
    cases: Vec<Case>,
}

#[test]
fn thin_film_reflectance_agrees_with_a_transfer_matrix_package() {
    let reference: Reference =
        serde_json::from_str(include_str!("optics_reference/coating.tmm.json")).unwrap();
    assert_eq!(
        (reference.layer_index, reference.design_nm),
        (MGF2_INDEX, DESIGN_NM)
    );
    let coated = Coating::default();
    let mut worst = 0.0f64;
    for case in &reference.cases {
        let cos = case.degrees.to_radians().cos();
        for (coating, expected) in [(coated, case.coated), (Coating::Uncoated, case.uncoated)] {
            let got = coating.reflectance(case.n_from, case.n_to, cos, case.lambda_nm);
            // Both are f64 evaluations of the same closed form by other arithmetic: within
            // 1e-9 absolute.
            let difference = (got - expected).abs();
            worst = worst.max(difference);
            assert!(
                difference < 1e-9,
                "{coating:?} from {} to {} at {} deg, {} nm: {got} against tmm's {expected}",
                case.n_from,
                case.n_to,
                case.degrees,
                case.lambda_nm
            );
        }
    }
    println!(
        "{} cases: largest difference from tmm {worst:.2e}",
        reference.cases.len()
    );
    // The layer's point: a crown surface at normal incidence reflects 4.2 % bare and 1.3 %
    // coated at 550 nm, and a reflection from either side is the same.
    let bare = Coating::Uncoated.reflectance(1.0, 1.5168, 1.0, 550.0);
    let layer = coated.reflectance(1.0, 1.5168, 1.0, 550.0);
    assert!(
        (bare - 0.0422).abs() < 1e-4 && (layer - 0.0128).abs() < 1e-4,
        "{bare} {layer}"
    );
    let back = coated.reflectance(1.5168, 1.0, 1.0, 550.0);
    assert!((back - layer).abs() < 1e-12, "{back} against {layer}");
}
