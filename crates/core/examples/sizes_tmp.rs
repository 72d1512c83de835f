fn main() {
    use relnav_core::estimators::*;
    use relnav_core::nav::*;
    println!("Navigator {}", core::mem::size_of::<Navigator>());
    println!("AnyFilter {}", core::mem::size_of::<relnav_core::nav::factory::AnyFilter>());
    println!("Aqukf {}", core::mem::size_of::<Aqukf>());
    println!("Imm {}", core::mem::size_of::<Imm>());
    println!("Ukf {}", core::mem::size_of::<Ukf>());
    println!("Ekf {}", core::mem::size_of::<Ekf>());
    println!("NavConfig {}", core::mem::size_of::<NavConfig>());
}
