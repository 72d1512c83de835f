//! The shared library of `relnav_guidance.fmu`: every FMI 2.0 co-simulation function and
//! every FMI 3.0 function, exported unprefixed for [`relnav_models::guidance::GuidanceFmu`]
//! (the hold-point guidance law; the model and its variable table live in relnav-models).
//! `relnav-fmu --all` packs it as `binaries/linux64/relnav_guidance.so` and, in
//! `relnav_guidance3.fmu`, `binaries/x86_64-linux/relnav_guidance.so`.

relnav_fmi::export_fmi2!(relnav_models::guidance::GuidanceFmu);
relnav_fmi::export_fmi3!(relnav_models::guidance::GuidanceFmu);
