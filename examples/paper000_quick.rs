//! Quick check of paper 000's example with the EKF and UKF (library API, no FMU).
use rand::SeedableRng;
use relnav::dynamics::CwModel;
use relnav::frames::Frame;
use relnav::nav::{FilterKind, NavConfig, Navigator};
use relnav::sensors::RadioSensor;
use relnav::types::{State, Vec3};

fn main() {
    for kind in [FilterKind::Ekf, FilterKind::Ukf] {
        let cfg = NavConfig { filter: kind, ..Default::default() };
        let f = cfg.frame;
        let model = CwModel::new(cfg.mean_motion);
        let sensor = RadioSensor::new(f, cfg.sigma_range, cfg.sigma_angle);
        let runs = 20;
        let steps = 600;
        let mut se = vec![[0.0f64; 6]; steps + 1];
        for run in 0..runs {
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(run);
            let mut nav = Navigator::new(&cfg).unwrap();
            let mut xt = f.state_to_canonical(&State::from_row_slice(&[400.0, 500.0, 200.0, 0.0, 0.0, 0.0]));
            for k in 0..steps {
                let z = sensor.measure(&xt.fixed_rows::<3>(0).into_owned(), &mut rng).unwrap();
                nav.step(&[0.0; 3], Some(&[z.x, z.y, z.z]), 1.0).unwrap();
                xt = model.propagate(&xt, &Vec3::zeros(), 1.0);
                let e = nav.state() - f.state_from_canonical(&xt);
                for i in 0..6 { se[k + 1][i] += e[i] * e[i] / runs as f64; }
            }
        }
        let mut worst = [0.0f64; 6];
        let mut pos = 0.0;
        for k in 80..=steps { for i in 0..6 { worst[i] = worst[i].max(se[k][i].sqrt()); } pos += se[k][0] + se[k][1] + se[k][2]; }
        let pos_rmse = (pos / (steps - 79) as f64).sqrt();
        println!("{kind:?}: worst per-axis RMSE after 80 s {:?}; pos RMSE 80-600 {pos_rmse:.4}", worst.map(|v| (v * 1e4).round() / 1e4));
        println!("  final sigma {:?}", (0..6).map(|i| se[steps][i].sqrt()).collect::<Vec<_>>());
    }
}
