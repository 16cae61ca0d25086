//! Table 6 of Velez et al. 2012: the time of one perception field over a vantage grid, by PBD
//! (eq. 32) and by explicit enumeration of the score over 10 and 100 bins (eq. 8), for the
//! sign detector's dynamic model trained on simulated looks, at a candidate with three looks.
//! The grid (8 ranges × 13 aspects) is the planned verifier's; its GP_ind predictions are made
//! once per model, as the planner does.
#![allow(
    missing_docs,
    reason = "criterion_group! generates an undocumented public function"
)]

use avs_eval::verification::{model_kind, profile_of, train_model, Strategy};
use avs_format::verification::DetectorName;
use avs_verify::field::{perception_field, FieldMethod, PreparedGrid, VantageGrid};
use avs_verify::sensor::Look;
use avs_verify::vantage::Vantage;
use criterion::{criterion_group, criterion_main, Criterion};

fn fields(c: &mut Criterion) {
    for detector in [DetectorName::Sign, DetectorName::Door] {
        let strategy = if detector == DetectorName::Door {
            Strategy::PlannedDisc
        } else {
            Strategy::Planned
        };
        let spec = train_model(&profile_of(detector), model_kind(strategy, detector), 1).unwrap();
        let model = avs_verify::sensor::SensorModel::from_spec(&spec).unwrap();
        let grid = PreparedGrid::new(&model, VantageGrid::for_model(&model, 8, 13));
        let looks = [
            Look {
                vantage: Vantage::new(3.0, 0.1),
                score: 1.6,
            },
            Look {
                vantage: Vantage::new(2.5, -0.3),
                score: 1.2,
            },
            Look {
                vantage: Vantage::new(4.0, 0.4),
                score: 1.9,
            },
        ];
        let cond = model.condition(&looks).unwrap();
        for (name, method) in [
            ("pbd", FieldMethod::Pbd),
            ("bins10", FieldMethod::Bins(10)),
            ("bins100", FieldMethod::Bins(100)),
        ] {
            c.bench_function(&format!("field_{}_{name}", detector.as_str()), |b| {
                b.iter(|| perception_field(&cond, 0.6, &grid, method))
            });
        }
    }
}

criterion_group!(benches, fields);
criterion_main!(benches);
