//! The shared library of `relnav_plant.fmu`: every FMI 2.0 co-simulation function, exported
//! unprefixed for [`relnav_models::plant::PlantFmu`] (the truth plant: true relative motion
//! and the radio/lidar sensor; the model and its variable table live in relnav-models).
//! `relnav-fmu --all` packs it as `binaries/linux64/relnav_plant.so`.

relnav_fmi::export_fmi2!(relnav_models::plant::PlantFmu);
