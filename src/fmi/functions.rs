//! The exported `fmi2*` entry points: [`crate::export_fmi2`] defines every FMI 2.0 common
//! and co-simulation function, unprefixed, for one [`super::model::Model`], forwarding to
//! the generic implementations of [`super::entry`]. relnav's own exports (relnav.fmu's
//! binary, the C-ABI library `librelnav.so`) are this macro applied to
//! [`super::relnav::RelnavFmu`], behind the default cargo feature `fmi-exports`; the kit's
//! FMUs (`fmu/plant`, `fmu/guidance`) are cdylib crates that apply it to their model and
//! link relnav without that feature (a shared library can export each `fmi2*` symbol
//! once).
#![allow(non_snake_case)]

/// Export the FMI 2.0 co-simulation functions of the [`Model`](crate::fmi::model::Model)
/// `$model` from the crate that invokes it (at most once per shared library: the symbols
/// are unprefixed). A cdylib crate that links relnav must disable relnav's default feature
/// `fmi-exports`, or its `fmi2*` symbols clash with relnav's own at link time.
#[macro_export]
macro_rules! export_fmi2 {
    ($model:ty) => {
        #[doc = concat!("`fmi2GetTypesPlatform` (FMI 2.0).")]
        #[no_mangle]
        pub extern "C" fn fmi2GetTypesPlatform() -> *const ::std::ffi::c_char {
            $crate::fmi::entry::fmi2GetTypesPlatform()
        }
        #[doc = concat!("`fmi2GetVersion` (FMI 2.0).")]
        #[no_mangle]
        pub extern "C" fn fmi2GetVersion() -> *const ::std::ffi::c_char {
            $crate::fmi::entry::fmi2GetVersion()
        }
        #[doc = concat!("`fmi2Instantiate` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2Instantiate(
            instanceName: $crate::fmi::types::fmi2String,
            fmuType: ::std::ffi::c_int,
            fmuGUID: $crate::fmi::types::fmi2String,
            fmuResourceLocation: $crate::fmi::types::fmi2String,
            functions: *const $crate::fmi::types::fmi2CallbackFunctions,
            visible: $crate::fmi::types::fmi2Boolean,
            loggingOn: $crate::fmi::types::fmi2Boolean,
        ) -> $crate::fmi::types::fmi2Component {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi::entry::fmi2Instantiate::<$model>(instanceName, fmuType, fmuGUID, fmuResourceLocation, functions, visible, loggingOn) }
        }
        #[doc = concat!("`fmi2FreeInstance` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2FreeInstance(
            c: $crate::fmi::types::fmi2Component,
        )  {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi::entry::fmi2FreeInstance::<$model>(c) }
        }
        #[doc = concat!("`fmi2SetDebugLogging` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2SetDebugLogging(
            c: $crate::fmi::types::fmi2Component,
            loggingOn: $crate::fmi::types::fmi2Boolean,
            nCategories: usize,
            categories: *const $crate::fmi::types::fmi2String,
        ) -> $crate::fmi::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi::entry::fmi2SetDebugLogging::<$model>(c, loggingOn, nCategories, categories) }
        }
        #[doc = concat!("`fmi2SetupExperiment` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2SetupExperiment(
            c: $crate::fmi::types::fmi2Component,
            toleranceDefined: $crate::fmi::types::fmi2Boolean,
            tolerance: $crate::fmi::types::fmi2Real,
            startTime: $crate::fmi::types::fmi2Real,
            stopTimeDefined: $crate::fmi::types::fmi2Boolean,
            stopTime: $crate::fmi::types::fmi2Real,
        ) -> $crate::fmi::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi::entry::fmi2SetupExperiment::<$model>(c, toleranceDefined, tolerance, startTime, stopTimeDefined, stopTime) }
        }
        #[doc = concat!("`fmi2EnterInitializationMode` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2EnterInitializationMode(
            c: $crate::fmi::types::fmi2Component,
        ) -> $crate::fmi::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi::entry::fmi2EnterInitializationMode::<$model>(c) }
        }
        #[doc = concat!("`fmi2ExitInitializationMode` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2ExitInitializationMode(
            c: $crate::fmi::types::fmi2Component,
        ) -> $crate::fmi::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi::entry::fmi2ExitInitializationMode::<$model>(c) }
        }
        #[doc = concat!("`fmi2Terminate` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2Terminate(
            c: $crate::fmi::types::fmi2Component,
        ) -> $crate::fmi::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi::entry::fmi2Terminate::<$model>(c) }
        }
        #[doc = concat!("`fmi2Reset` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2Reset(
            c: $crate::fmi::types::fmi2Component,
        ) -> $crate::fmi::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi::entry::fmi2Reset::<$model>(c) }
        }
        #[doc = concat!("`fmi2GetReal` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2GetReal(
            c: $crate::fmi::types::fmi2Component,
            vr: *const $crate::fmi::types::fmi2ValueReference,
            nvr: usize,
            value: *mut $crate::fmi::types::fmi2Real,
        ) -> $crate::fmi::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi::entry::fmi2GetReal::<$model>(c, vr, nvr, value) }
        }
        #[doc = concat!("`fmi2GetInteger` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2GetInteger(
            c: $crate::fmi::types::fmi2Component,
            vr: *const $crate::fmi::types::fmi2ValueReference,
            nvr: usize,
            value: *mut $crate::fmi::types::fmi2Integer,
        ) -> $crate::fmi::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi::entry::fmi2GetInteger::<$model>(c, vr, nvr, value) }
        }
        #[doc = concat!("`fmi2GetBoolean` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2GetBoolean(
            c: $crate::fmi::types::fmi2Component,
            vr: *const $crate::fmi::types::fmi2ValueReference,
            nvr: usize,
            value: *mut $crate::fmi::types::fmi2Boolean,
        ) -> $crate::fmi::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi::entry::fmi2GetBoolean::<$model>(c, vr, nvr, value) }
        }
        #[doc = concat!("`fmi2GetString` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2GetString(
            c: $crate::fmi::types::fmi2Component,
            vr: *const $crate::fmi::types::fmi2ValueReference,
            nvr: usize,
            value: *mut $crate::fmi::types::fmi2String,
        ) -> $crate::fmi::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi::entry::fmi2GetString::<$model>(c, vr, nvr, value) }
        }
        #[doc = concat!("`fmi2SetReal` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2SetReal(
            c: $crate::fmi::types::fmi2Component,
            vr: *const $crate::fmi::types::fmi2ValueReference,
            nvr: usize,
            value: *const $crate::fmi::types::fmi2Real,
        ) -> $crate::fmi::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi::entry::fmi2SetReal::<$model>(c, vr, nvr, value) }
        }
        #[doc = concat!("`fmi2SetInteger` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2SetInteger(
            c: $crate::fmi::types::fmi2Component,
            vr: *const $crate::fmi::types::fmi2ValueReference,
            nvr: usize,
            value: *const $crate::fmi::types::fmi2Integer,
        ) -> $crate::fmi::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi::entry::fmi2SetInteger::<$model>(c, vr, nvr, value) }
        }
        #[doc = concat!("`fmi2SetBoolean` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2SetBoolean(
            c: $crate::fmi::types::fmi2Component,
            vr: *const $crate::fmi::types::fmi2ValueReference,
            nvr: usize,
            value: *const $crate::fmi::types::fmi2Boolean,
        ) -> $crate::fmi::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi::entry::fmi2SetBoolean::<$model>(c, vr, nvr, value) }
        }
        #[doc = concat!("`fmi2SetString` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2SetString(
            c: $crate::fmi::types::fmi2Component,
            vr: *const $crate::fmi::types::fmi2ValueReference,
            nvr: usize,
            value: *const $crate::fmi::types::fmi2String,
        ) -> $crate::fmi::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi::entry::fmi2SetString::<$model>(c, vr, nvr, value) }
        }
        #[doc = concat!("`fmi2GetFMUstate` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2GetFMUstate(
            c: $crate::fmi::types::fmi2Component,
            FMUstate: *mut $crate::fmi::types::fmi2FMUstate,
        ) -> $crate::fmi::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi::entry::fmi2GetFMUstate::<$model>(c, FMUstate) }
        }
        #[doc = concat!("`fmi2SetFMUstate` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2SetFMUstate(
            c: $crate::fmi::types::fmi2Component,
            FMUstate: $crate::fmi::types::fmi2FMUstate,
        ) -> $crate::fmi::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi::entry::fmi2SetFMUstate::<$model>(c, FMUstate) }
        }
        #[doc = concat!("`fmi2FreeFMUstate` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2FreeFMUstate(
            c: $crate::fmi::types::fmi2Component,
            FMUstate: *mut $crate::fmi::types::fmi2FMUstate,
        ) -> $crate::fmi::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi::entry::fmi2FreeFMUstate::<$model>(c, FMUstate) }
        }
        #[doc = concat!("`fmi2SerializedFMUstateSize` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2SerializedFMUstateSize(
            c: $crate::fmi::types::fmi2Component,
            FMUstate: $crate::fmi::types::fmi2FMUstate,
            size: *mut usize,
        ) -> $crate::fmi::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi::entry::fmi2SerializedFMUstateSize::<$model>(c, FMUstate, size) }
        }
        #[doc = concat!("`fmi2SerializeFMUstate` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2SerializeFMUstate(
            c: $crate::fmi::types::fmi2Component,
            FMUstate: $crate::fmi::types::fmi2FMUstate,
            serializedState: *mut $crate::fmi::types::fmi2Byte,
            size: usize,
        ) -> $crate::fmi::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi::entry::fmi2SerializeFMUstate::<$model>(c, FMUstate, serializedState, size) }
        }
        #[doc = concat!("`fmi2DeSerializeFMUstate` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2DeSerializeFMUstate(
            c: $crate::fmi::types::fmi2Component,
            serializedState: *const $crate::fmi::types::fmi2Byte,
            size: usize,
            FMUstate: *mut $crate::fmi::types::fmi2FMUstate,
        ) -> $crate::fmi::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi::entry::fmi2DeSerializeFMUstate::<$model>(c, serializedState, size, FMUstate) }
        }
        #[doc = concat!("`fmi2GetDirectionalDerivative` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2GetDirectionalDerivative(
            c: $crate::fmi::types::fmi2Component,
            vu: *const $crate::fmi::types::fmi2ValueReference,
            nu: usize,
            vk: *const $crate::fmi::types::fmi2ValueReference,
            nk: usize,
            dvk: *const $crate::fmi::types::fmi2Real,
            dvu: *mut $crate::fmi::types::fmi2Real,
        ) -> $crate::fmi::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi::entry::fmi2GetDirectionalDerivative::<$model>(c, vu, nu, vk, nk, dvk, dvu) }
        }
        #[doc = concat!("`fmi2SetRealInputDerivatives` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2SetRealInputDerivatives(
            c: $crate::fmi::types::fmi2Component,
            vr: *const $crate::fmi::types::fmi2ValueReference,
            nvr: usize,
            order: *const $crate::fmi::types::fmi2Integer,
            value: *const $crate::fmi::types::fmi2Real,
        ) -> $crate::fmi::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi::entry::fmi2SetRealInputDerivatives::<$model>(c, vr, nvr, order, value) }
        }
        #[doc = concat!("`fmi2GetRealOutputDerivatives` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2GetRealOutputDerivatives(
            c: $crate::fmi::types::fmi2Component,
            vr: *const $crate::fmi::types::fmi2ValueReference,
            nvr: usize,
            order: *const $crate::fmi::types::fmi2Integer,
            value: *mut $crate::fmi::types::fmi2Real,
        ) -> $crate::fmi::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi::entry::fmi2GetRealOutputDerivatives::<$model>(c, vr, nvr, order, value) }
        }
        #[doc = concat!("`fmi2DoStep` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2DoStep(
            c: $crate::fmi::types::fmi2Component,
            currentCommunicationPoint: $crate::fmi::types::fmi2Real,
            communicationStepSize: $crate::fmi::types::fmi2Real,
            noSetFMUStatePriorToCurrentPoint: $crate::fmi::types::fmi2Boolean,
        ) -> $crate::fmi::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi::entry::fmi2DoStep::<$model>(c, currentCommunicationPoint, communicationStepSize, noSetFMUStatePriorToCurrentPoint) }
        }
        #[doc = concat!("`fmi2CancelStep` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2CancelStep(
            c: $crate::fmi::types::fmi2Component,
        ) -> $crate::fmi::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi::entry::fmi2CancelStep::<$model>(c) }
        }
        #[doc = concat!("`fmi2GetStatus` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2GetStatus(
            c: $crate::fmi::types::fmi2Component,
            s: ::std::ffi::c_int,
            value: *mut ::std::ffi::c_int,
        ) -> $crate::fmi::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi::entry::fmi2GetStatus::<$model>(c, s, value) }
        }
        #[doc = concat!("`fmi2GetRealStatus` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2GetRealStatus(
            c: $crate::fmi::types::fmi2Component,
            s: ::std::ffi::c_int,
            value: *mut $crate::fmi::types::fmi2Real,
        ) -> $crate::fmi::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi::entry::fmi2GetRealStatus::<$model>(c, s, value) }
        }
        #[doc = concat!("`fmi2GetIntegerStatus` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2GetIntegerStatus(
            c: $crate::fmi::types::fmi2Component,
            s: ::std::ffi::c_int,
            value: *mut $crate::fmi::types::fmi2Integer,
        ) -> $crate::fmi::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi::entry::fmi2GetIntegerStatus::<$model>(c, s, value) }
        }
        #[doc = concat!("`fmi2GetBooleanStatus` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2GetBooleanStatus(
            c: $crate::fmi::types::fmi2Component,
            s: ::std::ffi::c_int,
            value: *mut $crate::fmi::types::fmi2Boolean,
        ) -> $crate::fmi::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi::entry::fmi2GetBooleanStatus::<$model>(c, s, value) }
        }
        #[doc = concat!("`fmi2GetStringStatus` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2GetStringStatus(
            c: $crate::fmi::types::fmi2Component,
            s: ::std::ffi::c_int,
            value: *mut $crate::fmi::types::fmi2String,
        ) -> $crate::fmi::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi::entry::fmi2GetStringStatus::<$model>(c, s, value) }
        }
    };
}

#[cfg(feature = "fmi-exports")]
crate::export_fmi2!(super::relnav::RelnavFmu);
