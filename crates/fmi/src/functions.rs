//! The exported `fmi2*` entry points: [`crate::export_fmi2`] defines every FMI 2.0 common
//! and co-simulation function, unprefixed, for one [`crate::model::Model`], forwarding to
//! the generic implementations of [`crate::entry`]. relnav's own exports (relnav.fmu's
//! binary, the C-ABI library `librelnav.so`) are this macro applied to
//! [`crate::relnav::RelnavFmu`], behind the default cargo feature `fmi-exports`; the kit's
//! FMUs (`fmu/plant`, `fmu/guidance`) are cdylib crates that apply it to their model and
//! link relnav without that feature (a shared library can export each `fmi2*` symbol
//! once).
#![allow(non_snake_case)]

/// Export the FMI 2.0 co-simulation functions of the [`Model`](crate::model::Model)
/// `$model` from the crate that invokes it (at most once per shared library: the symbols
/// are unprefixed). A cdylib crate that links relnav must disable relnav's default feature
/// `fmi-exports`, or its `fmi2*` symbols clash with relnav's own at link time.
#[macro_export]
macro_rules! export_fmi2 {
    ($model:ty) => {
        #[doc = concat!("`fmi2GetTypesPlatform` (FMI 2.0).")]
        #[no_mangle]
        pub extern "C" fn fmi2GetTypesPlatform() -> *const ::std::ffi::c_char {
            $crate::entry::fmi2GetTypesPlatform()
        }
        #[doc = concat!("`fmi2GetVersion` (FMI 2.0).")]
        #[no_mangle]
        pub extern "C" fn fmi2GetVersion() -> *const ::std::ffi::c_char {
            $crate::entry::fmi2GetVersion()
        }
        #[doc = concat!("`fmi2Instantiate` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2Instantiate(
            instanceName: $crate::types::fmi2String,
            fmuType: ::std::ffi::c_int,
            fmuGUID: $crate::types::fmi2String,
            fmuResourceLocation: $crate::types::fmi2String,
            functions: *const $crate::types::fmi2CallbackFunctions,
            visible: $crate::types::fmi2Boolean,
            loggingOn: $crate::types::fmi2Boolean,
        ) -> $crate::types::fmi2Component {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::entry::fmi2Instantiate::<$model>(instanceName, fmuType, fmuGUID, fmuResourceLocation, functions, visible, loggingOn) }
        }
        #[doc = concat!("`fmi2FreeInstance` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2FreeInstance(
            c: $crate::types::fmi2Component,
        )  {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::entry::fmi2FreeInstance::<$model>(c) }
        }
        #[doc = concat!("`fmi2SetDebugLogging` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2SetDebugLogging(
            c: $crate::types::fmi2Component,
            loggingOn: $crate::types::fmi2Boolean,
            nCategories: usize,
            categories: *const $crate::types::fmi2String,
        ) -> $crate::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::entry::fmi2SetDebugLogging::<$model>(c, loggingOn, nCategories, categories) }
        }
        #[doc = concat!("`fmi2SetupExperiment` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2SetupExperiment(
            c: $crate::types::fmi2Component,
            toleranceDefined: $crate::types::fmi2Boolean,
            tolerance: $crate::types::fmi2Real,
            startTime: $crate::types::fmi2Real,
            stopTimeDefined: $crate::types::fmi2Boolean,
            stopTime: $crate::types::fmi2Real,
        ) -> $crate::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::entry::fmi2SetupExperiment::<$model>(c, toleranceDefined, tolerance, startTime, stopTimeDefined, stopTime) }
        }
        #[doc = concat!("`fmi2EnterInitializationMode` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2EnterInitializationMode(
            c: $crate::types::fmi2Component,
        ) -> $crate::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::entry::fmi2EnterInitializationMode::<$model>(c) }
        }
        #[doc = concat!("`fmi2ExitInitializationMode` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2ExitInitializationMode(
            c: $crate::types::fmi2Component,
        ) -> $crate::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::entry::fmi2ExitInitializationMode::<$model>(c) }
        }
        #[doc = concat!("`fmi2Terminate` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2Terminate(
            c: $crate::types::fmi2Component,
        ) -> $crate::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::entry::fmi2Terminate::<$model>(c) }
        }
        #[doc = concat!("`fmi2Reset` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2Reset(
            c: $crate::types::fmi2Component,
        ) -> $crate::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::entry::fmi2Reset::<$model>(c) }
        }
        #[doc = concat!("`fmi2GetReal` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2GetReal(
            c: $crate::types::fmi2Component,
            vr: *const $crate::types::fmi2ValueReference,
            nvr: usize,
            value: *mut $crate::types::fmi2Real,
        ) -> $crate::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::entry::fmi2GetReal::<$model>(c, vr, nvr, value) }
        }
        #[doc = concat!("`fmi2GetInteger` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2GetInteger(
            c: $crate::types::fmi2Component,
            vr: *const $crate::types::fmi2ValueReference,
            nvr: usize,
            value: *mut $crate::types::fmi2Integer,
        ) -> $crate::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::entry::fmi2GetInteger::<$model>(c, vr, nvr, value) }
        }
        #[doc = concat!("`fmi2GetBoolean` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2GetBoolean(
            c: $crate::types::fmi2Component,
            vr: *const $crate::types::fmi2ValueReference,
            nvr: usize,
            value: *mut $crate::types::fmi2Boolean,
        ) -> $crate::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::entry::fmi2GetBoolean::<$model>(c, vr, nvr, value) }
        }
        #[doc = concat!("`fmi2GetString` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2GetString(
            c: $crate::types::fmi2Component,
            vr: *const $crate::types::fmi2ValueReference,
            nvr: usize,
            value: *mut $crate::types::fmi2String,
        ) -> $crate::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::entry::fmi2GetString::<$model>(c, vr, nvr, value) }
        }
        #[doc = concat!("`fmi2SetReal` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2SetReal(
            c: $crate::types::fmi2Component,
            vr: *const $crate::types::fmi2ValueReference,
            nvr: usize,
            value: *const $crate::types::fmi2Real,
        ) -> $crate::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::entry::fmi2SetReal::<$model>(c, vr, nvr, value) }
        }
        #[doc = concat!("`fmi2SetInteger` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2SetInteger(
            c: $crate::types::fmi2Component,
            vr: *const $crate::types::fmi2ValueReference,
            nvr: usize,
            value: *const $crate::types::fmi2Integer,
        ) -> $crate::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::entry::fmi2SetInteger::<$model>(c, vr, nvr, value) }
        }
        #[doc = concat!("`fmi2SetBoolean` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2SetBoolean(
            c: $crate::types::fmi2Component,
            vr: *const $crate::types::fmi2ValueReference,
            nvr: usize,
            value: *const $crate::types::fmi2Boolean,
        ) -> $crate::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::entry::fmi2SetBoolean::<$model>(c, vr, nvr, value) }
        }
        #[doc = concat!("`fmi2SetString` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2SetString(
            c: $crate::types::fmi2Component,
            vr: *const $crate::types::fmi2ValueReference,
            nvr: usize,
            value: *const $crate::types::fmi2String,
        ) -> $crate::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::entry::fmi2SetString::<$model>(c, vr, nvr, value) }
        }
        #[doc = concat!("`fmi2GetFMUstate` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2GetFMUstate(
            c: $crate::types::fmi2Component,
            FMUstate: *mut $crate::types::fmi2FMUstate,
        ) -> $crate::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::entry::fmi2GetFMUstate::<$model>(c, FMUstate) }
        }
        #[doc = concat!("`fmi2SetFMUstate` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2SetFMUstate(
            c: $crate::types::fmi2Component,
            FMUstate: $crate::types::fmi2FMUstate,
        ) -> $crate::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::entry::fmi2SetFMUstate::<$model>(c, FMUstate) }
        }
        #[doc = concat!("`fmi2FreeFMUstate` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2FreeFMUstate(
            c: $crate::types::fmi2Component,
            FMUstate: *mut $crate::types::fmi2FMUstate,
        ) -> $crate::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::entry::fmi2FreeFMUstate::<$model>(c, FMUstate) }
        }
        #[doc = concat!("`fmi2SerializedFMUstateSize` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2SerializedFMUstateSize(
            c: $crate::types::fmi2Component,
            FMUstate: $crate::types::fmi2FMUstate,
            size: *mut usize,
        ) -> $crate::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::entry::fmi2SerializedFMUstateSize::<$model>(c, FMUstate, size) }
        }
        #[doc = concat!("`fmi2SerializeFMUstate` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2SerializeFMUstate(
            c: $crate::types::fmi2Component,
            FMUstate: $crate::types::fmi2FMUstate,
            serializedState: *mut $crate::types::fmi2Byte,
            size: usize,
        ) -> $crate::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::entry::fmi2SerializeFMUstate::<$model>(c, FMUstate, serializedState, size) }
        }
        #[doc = concat!("`fmi2DeSerializeFMUstate` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2DeSerializeFMUstate(
            c: $crate::types::fmi2Component,
            serializedState: *const $crate::types::fmi2Byte,
            size: usize,
            FMUstate: *mut $crate::types::fmi2FMUstate,
        ) -> $crate::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::entry::fmi2DeSerializeFMUstate::<$model>(c, serializedState, size, FMUstate) }
        }
        #[doc = concat!("`fmi2GetDirectionalDerivative` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2GetDirectionalDerivative(
            c: $crate::types::fmi2Component,
            vu: *const $crate::types::fmi2ValueReference,
            nu: usize,
            vk: *const $crate::types::fmi2ValueReference,
            nk: usize,
            dvk: *const $crate::types::fmi2Real,
            dvu: *mut $crate::types::fmi2Real,
        ) -> $crate::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::entry::fmi2GetDirectionalDerivative::<$model>(c, vu, nu, vk, nk, dvk, dvu) }
        }
        #[doc = concat!("`fmi2SetRealInputDerivatives` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2SetRealInputDerivatives(
            c: $crate::types::fmi2Component,
            vr: *const $crate::types::fmi2ValueReference,
            nvr: usize,
            order: *const $crate::types::fmi2Integer,
            value: *const $crate::types::fmi2Real,
        ) -> $crate::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::entry::fmi2SetRealInputDerivatives::<$model>(c, vr, nvr, order, value) }
        }
        #[doc = concat!("`fmi2GetRealOutputDerivatives` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2GetRealOutputDerivatives(
            c: $crate::types::fmi2Component,
            vr: *const $crate::types::fmi2ValueReference,
            nvr: usize,
            order: *const $crate::types::fmi2Integer,
            value: *mut $crate::types::fmi2Real,
        ) -> $crate::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::entry::fmi2GetRealOutputDerivatives::<$model>(c, vr, nvr, order, value) }
        }
        #[doc = concat!("`fmi2DoStep` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2DoStep(
            c: $crate::types::fmi2Component,
            currentCommunicationPoint: $crate::types::fmi2Real,
            communicationStepSize: $crate::types::fmi2Real,
            noSetFMUStatePriorToCurrentPoint: $crate::types::fmi2Boolean,
        ) -> $crate::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::entry::fmi2DoStep::<$model>(c, currentCommunicationPoint, communicationStepSize, noSetFMUStatePriorToCurrentPoint) }
        }
        #[doc = concat!("`fmi2CancelStep` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2CancelStep(
            c: $crate::types::fmi2Component,
        ) -> $crate::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::entry::fmi2CancelStep::<$model>(c) }
        }
        #[doc = concat!("`fmi2GetStatus` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2GetStatus(
            c: $crate::types::fmi2Component,
            s: ::std::ffi::c_int,
            value: *mut ::std::ffi::c_int,
        ) -> $crate::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::entry::fmi2GetStatus::<$model>(c, s, value) }
        }
        #[doc = concat!("`fmi2GetRealStatus` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2GetRealStatus(
            c: $crate::types::fmi2Component,
            s: ::std::ffi::c_int,
            value: *mut $crate::types::fmi2Real,
        ) -> $crate::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::entry::fmi2GetRealStatus::<$model>(c, s, value) }
        }
        #[doc = concat!("`fmi2GetIntegerStatus` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2GetIntegerStatus(
            c: $crate::types::fmi2Component,
            s: ::std::ffi::c_int,
            value: *mut $crate::types::fmi2Integer,
        ) -> $crate::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::entry::fmi2GetIntegerStatus::<$model>(c, s, value) }
        }
        #[doc = concat!("`fmi2GetBooleanStatus` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2GetBooleanStatus(
            c: $crate::types::fmi2Component,
            s: ::std::ffi::c_int,
            value: *mut $crate::types::fmi2Boolean,
        ) -> $crate::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::entry::fmi2GetBooleanStatus::<$model>(c, s, value) }
        }
        #[doc = concat!("`fmi2GetStringStatus` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2GetStringStatus(
            c: $crate::types::fmi2Component,
            s: ::std::ffi::c_int,
            value: *mut $crate::types::fmi2String,
        ) -> $crate::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::entry::fmi2GetStringStatus::<$model>(c, s, value) }
        }
    };
}

#[cfg(feature = "fmi-exports")]
crate::export_fmi2!(crate::relnav::RelnavFmu);
