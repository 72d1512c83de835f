//! The shared library of `relnav_guidance.fmu`: every FMI 2.0 co-simulation function,
//! exported unprefixed for [`relnav_models::guidance::GuidanceFmu`] (the hold-point
//! guidance law; the model and its variable table live in relnav-models). `relnav-fmu
//! --all` packs it as `binaries/linux64/relnav_guidance.so`.

relnav_fmi::export_fmi2!(relnav_models::guidance::GuidanceFmu);
