//! The shared library of `relnav_plant.fmu`: every FMI 2.0 co-simulation function and
//! every FMI 3.0 function, exported unprefixed for [`relnav_models::plant::PlantFmu`] (the
//! truth plant: true relative motion and the radio/lidar sensor; the model and its variable
//! table live in relnav-models).
//! `relnav-fmu --all` packs it as `binaries/linux64/relnav_plant.so` and, in
//! `relnav_plant3.fmu`, `binaries/x86_64-linux/relnav_plant.so`.

relnav_fmi::export_fmi2!(relnav_models::plant::PlantFmu);
relnav_fmi::export_fmi3!(relnav_models::plant::PlantFmu);
