//! The shared library of `relnav.fmu` and `relnav3.fmu`: every FMI 2.0 co-simulation
//! function and every FMI 3.0 function, exported unprefixed for
//! [`relnav_nav_model::RelnavFmu`] (the model and its variable table live in
//! relnav-nav-model), and the C ABI of the `relnav` crate beside them (`relnav_*`), as in
//! `librelnav.so`. `relnav-fmu` packs it as `binaries/linux64/relnav.so` and
//! `binaries/x86_64-linux/relnav.so`.

relnav_fmi::export_fmi2!(relnav_nav_model::RelnavFmu);
relnav_fmi::export_fmi3!(relnav_nav_model::RelnavFmu);

// the C ABI's exports come with the crate
use relnav as _;
