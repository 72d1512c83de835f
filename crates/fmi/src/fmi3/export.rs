//! The exported `fmi3*` entry points: [`crate::export_fmi3`] defines every function of the
//! FMI 3.0 standard (`fmi3FunctionTypes.h`: common, Model Exchange, Co-Simulation and
//! Scheduled Execution), unprefixed, for one [`crate::model::Model`]: the Co-Simulation
//! ones forward to [`crate::fmi3::functions`], the others return `fmi3Error` (or null for
//! the other instantiations) with the reason logged. Only the FMUs' shared libraries invoke
//! it, one model each, beside [`crate::export_fmi2`] (the two sets of names are disjoint).

/// Export every FMI 3.0 function for the [`Model`](crate::model::Model) `$model` from the
/// crate that invokes it (at most once per binary: the symbols are unprefixed).
#[macro_export]
macro_rules! export_fmi3 {
    ($model:ty) => {
        #[doc = "`fmi3GetVersion` (FMI 3.0)."]
        #[no_mangle]
        pub extern "C" fn fmi3GetVersion() -> *const ::std::ffi::c_char {
            $crate::fmi3::functions::fmi3GetVersion()
        }
        #[doc = "`fmi3InstantiateModelExchange` (FMI 3.0): null (Co-Simulation only), the reason logged."]
        #[no_mangle]
        pub extern "C" fn fmi3InstantiateModelExchange(
            _instanceName: $crate::fmi3::types::fmi3String,
            _instantiationToken: $crate::fmi3::types::fmi3String,
            _resourcePath: $crate::fmi3::types::fmi3String,
            _visible: bool,
            _loggingOn: bool,
            instanceEnvironment: $crate::fmi3::types::fmi3InstanceEnvironment,
            logMessage: $crate::fmi3::types::fmi3LogMessageCallback,
        ) -> $crate::fmi3::types::fmi3Instance {
            $crate::fmi3::functions::refuse_instantiation("fmi3InstantiateModelExchange", instanceEnvironment, logMessage, "Model Exchange")
        }
        #[doc = "`fmi3InstantiateScheduledExecution` (FMI 3.0): null (Co-Simulation only), the reason logged."]
        #[no_mangle]
        pub extern "C" fn fmi3InstantiateScheduledExecution(
            _instanceName: $crate::fmi3::types::fmi3String,
            _instantiationToken: $crate::fmi3::types::fmi3String,
            _resourcePath: $crate::fmi3::types::fmi3String,
            _visible: bool,
            _loggingOn: bool,
            instanceEnvironment: $crate::fmi3::types::fmi3InstanceEnvironment,
            logMessage: $crate::fmi3::types::fmi3LogMessageCallback,
            _clockUpdate: $crate::fmi3::types::fmi3ClockUpdateCallback,
            _lockPreemption: $crate::fmi3::types::fmi3LockPreemptionCallback,
            _unlockPreemption: $crate::fmi3::types::fmi3LockPreemptionCallback,
        ) -> $crate::fmi3::types::fmi3Instance {
            $crate::fmi3::functions::refuse_instantiation("fmi3InstantiateScheduledExecution", instanceEnvironment, logMessage, "Scheduled Execution")
        }
        #[doc = concat!("`fmi3InstantiateCoSimulation` (FMI 3.0) of `", stringify!($model), "`: a Co-Simulation instance.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 3.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3InstantiateCoSimulation(instanceName: $crate::fmi3::types::fmi3String, instantiationToken: $crate::fmi3::types::fmi3String, resourcePath: $crate::fmi3::types::fmi3String, visible: bool, loggingOn: bool, eventModeUsed: bool, earlyReturnAllowed: bool, requiredIntermediateVariables: *const $crate::fmi3::types::fmi3ValueReference, nRequiredIntermediateVariables: usize, instanceEnvironment: $crate::fmi3::types::fmi3InstanceEnvironment, logMessage: $crate::fmi3::types::fmi3LogMessageCallback, intermediateUpdate: $crate::fmi3::types::fmi3IntermediateUpdateCallback) -> $crate::fmi3::types::fmi3Instance {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::fmi3InstantiateCoSimulation::<$model>(instanceName, instantiationToken, resourcePath, visible, loggingOn, eventModeUsed, earlyReturnAllowed, requiredIntermediateVariables, nRequiredIntermediateVariables, instanceEnvironment, logMessage, intermediateUpdate) }
        }
        #[doc = concat!("`fmi3FreeInstance` (FMI 3.0) of `", stringify!($model), "`: release an instance.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 3.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3FreeInstance(instance: $crate::fmi3::types::fmi3Instance) {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::fmi3FreeInstance::<$model>(instance) }
        }
        #[doc = concat!("`fmi3SetDebugLogging` (FMI 3.0) of `", stringify!($model), "`: logging categories.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 3.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3SetDebugLogging(instance: $crate::fmi3::types::fmi3Instance, loggingOn: bool, nCategories: usize, categories: *const $crate::fmi3::types::fmi3String) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::fmi3SetDebugLogging::<$model>(instance, loggingOn, nCategories, categories) }
        }
        #[doc = concat!("`fmi3EnterInitializationMode` (FMI 3.0) of `", stringify!($model), "`: enter Initialization Mode.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 3.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3EnterInitializationMode(instance: $crate::fmi3::types::fmi3Instance, toleranceDefined: bool, tolerance: f64, startTime: f64, stopTimeDefined: bool, stopTime: f64) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::fmi3EnterInitializationMode::<$model>(instance, toleranceDefined, tolerance, startTime, stopTimeDefined, stopTime) }
        }
        #[doc = concat!("`fmi3ExitInitializationMode` (FMI 3.0) of `", stringify!($model), "`: exit Initialization Mode into Step Mode.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 3.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3ExitInitializationMode(instance: $crate::fmi3::types::fmi3Instance) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::fmi3ExitInitializationMode::<$model>(instance) }
        }
        #[doc = concat!("`fmi3EnterEventMode` (FMI 3.0) of `", stringify!($model), "`: Event Mode (models with it).")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 3.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3EnterEventMode(instance: $crate::fmi3::types::fmi3Instance) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::fmi3EnterEventMode::<$model>(instance) }
        }
        #[doc = concat!("`fmi3EnterStepMode` (FMI 3.0) of `", stringify!($model), "`: Event Mode (models with it).")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 3.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3EnterStepMode(instance: $crate::fmi3::types::fmi3Instance) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::fmi3EnterStepMode::<$model>(instance) }
        }
        #[doc = concat!("`fmi3Terminate` (FMI 3.0) of `", stringify!($model), "`: terminate.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 3.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3Terminate(instance: $crate::fmi3::types::fmi3Instance) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::fmi3Terminate::<$model>(instance) }
        }
        #[doc = concat!("`fmi3Reset` (FMI 3.0) of `", stringify!($model), "`: back to the start values.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 3.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3Reset(instance: $crate::fmi3::types::fmi3Instance) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::fmi3Reset::<$model>(instance) }
        }
        #[doc = concat!("`fmi3DoStep` (FMI 3.0) of `", stringify!($model), "`: one communication step.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 3.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3DoStep(instance: $crate::fmi3::types::fmi3Instance, currentCommunicationPoint: f64, communicationStepSize: f64, noSetFMUStatePriorToCurrentPoint: bool, eventHandlingNeeded: *mut bool, terminateSimulation: *mut bool, earlyReturn: *mut bool, lastSuccessfulTime: *mut f64) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::fmi3DoStep::<$model>(instance, currentCommunicationPoint, communicationStepSize, noSetFMUStatePriorToCurrentPoint, eventHandlingNeeded, terminateSimulation, earlyReturn, lastSuccessfulTime) }
        }
        #[doc = concat!("`fmi3GetFloat64` (FMI 3.0) of `", stringify!($model), "`: scalars and arrays.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 3.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3GetFloat64(instance: $crate::fmi3::types::fmi3Instance, valueReferences: *const $crate::fmi3::types::fmi3ValueReference, nValueReferences: usize, values: *mut f64, nValues: usize) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::fmi3GetFloat64::<$model>(instance, valueReferences, nValueReferences, values, nValues) }
        }
        #[doc = concat!("`fmi3SetFloat64` (FMI 3.0) of `", stringify!($model), "`: scalars and arrays.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 3.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3SetFloat64(instance: $crate::fmi3::types::fmi3Instance, valueReferences: *const $crate::fmi3::types::fmi3ValueReference, nValueReferences: usize, values: *const f64, nValues: usize) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::fmi3SetFloat64::<$model>(instance, valueReferences, nValueReferences, values, nValues) }
        }
        #[doc = concat!("`fmi3GetInt32` (FMI 3.0) of `", stringify!($model), "`: scalars and arrays.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 3.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3GetInt32(instance: $crate::fmi3::types::fmi3Instance, valueReferences: *const $crate::fmi3::types::fmi3ValueReference, nValueReferences: usize, values: *mut i32, nValues: usize) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::fmi3GetInt32::<$model>(instance, valueReferences, nValueReferences, values, nValues) }
        }
        #[doc = concat!("`fmi3SetInt32` (FMI 3.0) of `", stringify!($model), "`: scalars and arrays.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 3.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3SetInt32(instance: $crate::fmi3::types::fmi3Instance, valueReferences: *const $crate::fmi3::types::fmi3ValueReference, nValueReferences: usize, values: *const i32, nValues: usize) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::fmi3SetInt32::<$model>(instance, valueReferences, nValueReferences, values, nValues) }
        }
        #[doc = concat!("`fmi3GetBoolean` (FMI 3.0) of `", stringify!($model), "`: scalars and arrays.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 3.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3GetBoolean(instance: $crate::fmi3::types::fmi3Instance, valueReferences: *const $crate::fmi3::types::fmi3ValueReference, nValueReferences: usize, values: *mut bool, nValues: usize) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::fmi3GetBoolean::<$model>(instance, valueReferences, nValueReferences, values, nValues) }
        }
        #[doc = concat!("`fmi3SetBoolean` (FMI 3.0) of `", stringify!($model), "`: scalars and arrays.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 3.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3SetBoolean(instance: $crate::fmi3::types::fmi3Instance, valueReferences: *const $crate::fmi3::types::fmi3ValueReference, nValueReferences: usize, values: *const bool, nValues: usize) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::fmi3SetBoolean::<$model>(instance, valueReferences, nValueReferences, values, nValues) }
        }
        #[doc = concat!("`fmi3GetFMUState` (FMI 3.0) of `", stringify!($model), "`: copy the state.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 3.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3GetFMUState(instance: $crate::fmi3::types::fmi3Instance, FMUState: *mut $crate::fmi3::types::fmi3FMUState) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::fmi3GetFMUState::<$model>(instance, FMUState) }
        }
        #[doc = concat!("`fmi3SetFMUState` (FMI 3.0) of `", stringify!($model), "`: restore a state.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 3.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3SetFMUState(instance: $crate::fmi3::types::fmi3Instance, FMUState: $crate::fmi3::types::fmi3FMUState) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::fmi3SetFMUState::<$model>(instance, FMUState) }
        }
        #[doc = concat!("`fmi3FreeFMUState` (FMI 3.0) of `", stringify!($model), "`: free a state.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 3.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3FreeFMUState(instance: $crate::fmi3::types::fmi3Instance, FMUState: *mut $crate::fmi3::types::fmi3FMUState) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::fmi3FreeFMUState::<$model>(instance, FMUState) }
        }
        #[doc = concat!("`fmi3SerializedFMUStateSize` (FMI 3.0) of `", stringify!($model), "`: size of a serialised state.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 3.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3SerializedFMUStateSize(instance: $crate::fmi3::types::fmi3Instance, FMUState: $crate::fmi3::types::fmi3FMUState, size: *mut usize) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::fmi3SerializedFMUStateSize::<$model>(instance, FMUState, size) }
        }
        #[doc = concat!("`fmi3SerializeFMUState` (FMI 3.0) of `", stringify!($model), "`: serialise a state.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 3.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3SerializeFMUState(instance: $crate::fmi3::types::fmi3Instance, FMUState: $crate::fmi3::types::fmi3FMUState, serializedState: *mut u8, size: usize) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::fmi3SerializeFMUState::<$model>(instance, FMUState, serializedState, size) }
        }
        #[doc = concat!("`fmi3DeserializeFMUState` (FMI 3.0) of `", stringify!($model), "`: deserialise a state.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 3.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3DeserializeFMUState(instance: $crate::fmi3::types::fmi3Instance, serializedState: *const u8, size: usize, FMUState: *mut $crate::fmi3::types::fmi3FMUState) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::fmi3DeserializeFMUState::<$model>(instance, serializedState, size, FMUState) }
        }
        #[doc = concat!("`fmi3GetFloat32` (FMI 3.0) of `", stringify!($model), "`: refused (it has no Float32 variables).")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "`instance` is a live instance or null."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3GetFloat32(instance: $crate::fmi3::types::fmi3Instance, _vr: *const ::std::ffi::c_void, _nvr: usize, _values: *mut ::std::ffi::c_void, _n: usize) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::unsupported::<$model>(instance, "fmi3GetFloat32", "it has no Float32 variables") }
        }
        #[doc = concat!("`fmi3SetFloat32` (FMI 3.0) of `", stringify!($model), "`: refused (it has no Float32 variables).")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "`instance` is a live instance or null."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3SetFloat32(instance: $crate::fmi3::types::fmi3Instance, _vr: *const ::std::ffi::c_void, _nvr: usize, _values: *const ::std::ffi::c_void, _n: usize) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::unsupported::<$model>(instance, "fmi3SetFloat32", "it has no Float32 variables") }
        }
        #[doc = concat!("`fmi3GetInt8` (FMI 3.0) of `", stringify!($model), "`: refused (it has no Int8 variables).")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "`instance` is a live instance or null."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3GetInt8(instance: $crate::fmi3::types::fmi3Instance, _vr: *const ::std::ffi::c_void, _nvr: usize, _values: *mut ::std::ffi::c_void, _n: usize) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::unsupported::<$model>(instance, "fmi3GetInt8", "it has no Int8 variables") }
        }
        #[doc = concat!("`fmi3SetInt8` (FMI 3.0) of `", stringify!($model), "`: refused (it has no Int8 variables).")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "`instance` is a live instance or null."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3SetInt8(instance: $crate::fmi3::types::fmi3Instance, _vr: *const ::std::ffi::c_void, _nvr: usize, _values: *const ::std::ffi::c_void, _n: usize) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::unsupported::<$model>(instance, "fmi3SetInt8", "it has no Int8 variables") }
        }
        #[doc = concat!("`fmi3GetUInt8` (FMI 3.0) of `", stringify!($model), "`: refused (it has no UInt8 variables).")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "`instance` is a live instance or null."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3GetUInt8(instance: $crate::fmi3::types::fmi3Instance, _vr: *const ::std::ffi::c_void, _nvr: usize, _values: *mut ::std::ffi::c_void, _n: usize) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::unsupported::<$model>(instance, "fmi3GetUInt8", "it has no UInt8 variables") }
        }
        #[doc = concat!("`fmi3SetUInt8` (FMI 3.0) of `", stringify!($model), "`: refused (it has no UInt8 variables).")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "`instance` is a live instance or null."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3SetUInt8(instance: $crate::fmi3::types::fmi3Instance, _vr: *const ::std::ffi::c_void, _nvr: usize, _values: *const ::std::ffi::c_void, _n: usize) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::unsupported::<$model>(instance, "fmi3SetUInt8", "it has no UInt8 variables") }
        }
        #[doc = concat!("`fmi3GetInt16` (FMI 3.0) of `", stringify!($model), "`: refused (it has no Int16 variables).")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "`instance` is a live instance or null."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3GetInt16(instance: $crate::fmi3::types::fmi3Instance, _vr: *const ::std::ffi::c_void, _nvr: usize, _values: *mut ::std::ffi::c_void, _n: usize) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::unsupported::<$model>(instance, "fmi3GetInt16", "it has no Int16 variables") }
        }
        #[doc = concat!("`fmi3SetInt16` (FMI 3.0) of `", stringify!($model), "`: refused (it has no Int16 variables).")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "`instance` is a live instance or null."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3SetInt16(instance: $crate::fmi3::types::fmi3Instance, _vr: *const ::std::ffi::c_void, _nvr: usize, _values: *const ::std::ffi::c_void, _n: usize) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::unsupported::<$model>(instance, "fmi3SetInt16", "it has no Int16 variables") }
        }
        #[doc = concat!("`fmi3GetUInt16` (FMI 3.0) of `", stringify!($model), "`: refused (it has no UInt16 variables).")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "`instance` is a live instance or null."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3GetUInt16(instance: $crate::fmi3::types::fmi3Instance, _vr: *const ::std::ffi::c_void, _nvr: usize, _values: *mut ::std::ffi::c_void, _n: usize) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::unsupported::<$model>(instance, "fmi3GetUInt16", "it has no UInt16 variables") }
        }
        #[doc = concat!("`fmi3SetUInt16` (FMI 3.0) of `", stringify!($model), "`: refused (it has no UInt16 variables).")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "`instance` is a live instance or null."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3SetUInt16(instance: $crate::fmi3::types::fmi3Instance, _vr: *const ::std::ffi::c_void, _nvr: usize, _values: *const ::std::ffi::c_void, _n: usize) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::unsupported::<$model>(instance, "fmi3SetUInt16", "it has no UInt16 variables") }
        }
        #[doc = concat!("`fmi3GetUInt32` (FMI 3.0) of `", stringify!($model), "`: refused (it has no UInt32 variables).")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "`instance` is a live instance or null."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3GetUInt32(instance: $crate::fmi3::types::fmi3Instance, _vr: *const ::std::ffi::c_void, _nvr: usize, _values: *mut ::std::ffi::c_void, _n: usize) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::unsupported::<$model>(instance, "fmi3GetUInt32", "it has no UInt32 variables") }
        }
        #[doc = concat!("`fmi3SetUInt32` (FMI 3.0) of `", stringify!($model), "`: refused (it has no UInt32 variables).")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "`instance` is a live instance or null."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3SetUInt32(instance: $crate::fmi3::types::fmi3Instance, _vr: *const ::std::ffi::c_void, _nvr: usize, _values: *const ::std::ffi::c_void, _n: usize) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::unsupported::<$model>(instance, "fmi3SetUInt32", "it has no UInt32 variables") }
        }
        #[doc = concat!("`fmi3GetInt64` (FMI 3.0) of `", stringify!($model), "`: refused (it has no Int64 variables).")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "`instance` is a live instance or null."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3GetInt64(instance: $crate::fmi3::types::fmi3Instance, _vr: *const ::std::ffi::c_void, _nvr: usize, _values: *mut ::std::ffi::c_void, _n: usize) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::unsupported::<$model>(instance, "fmi3GetInt64", "it has no Int64 variables") }
        }
        #[doc = concat!("`fmi3SetInt64` (FMI 3.0) of `", stringify!($model), "`: refused (it has no Int64 variables).")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "`instance` is a live instance or null."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3SetInt64(instance: $crate::fmi3::types::fmi3Instance, _vr: *const ::std::ffi::c_void, _nvr: usize, _values: *const ::std::ffi::c_void, _n: usize) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::unsupported::<$model>(instance, "fmi3SetInt64", "it has no Int64 variables") }
        }
        #[doc = concat!("`fmi3GetUInt64` (FMI 3.0) of `", stringify!($model), "`: refused (it has no UInt64 variables).")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "`instance` is a live instance or null."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3GetUInt64(instance: $crate::fmi3::types::fmi3Instance, _vr: *const ::std::ffi::c_void, _nvr: usize, _values: *mut ::std::ffi::c_void, _n: usize) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::unsupported::<$model>(instance, "fmi3GetUInt64", "it has no UInt64 variables") }
        }
        #[doc = concat!("`fmi3SetUInt64` (FMI 3.0) of `", stringify!($model), "`: refused (it has no UInt64 variables).")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "`instance` is a live instance or null."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3SetUInt64(instance: $crate::fmi3::types::fmi3Instance, _vr: *const ::std::ffi::c_void, _nvr: usize, _values: *const ::std::ffi::c_void, _n: usize) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::unsupported::<$model>(instance, "fmi3SetUInt64", "it has no UInt64 variables") }
        }
        #[doc = concat!("`fmi3GetString` (FMI 3.0) of `", stringify!($model), "`: refused (it has no String variables).")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "`instance` is a live instance or null."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3GetString(instance: $crate::fmi3::types::fmi3Instance, _vr: *const ::std::ffi::c_void, _nvr: usize, _values: *mut ::std::ffi::c_void, _n: usize) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::unsupported::<$model>(instance, "fmi3GetString", "it has no String variables") }
        }
        #[doc = concat!("`fmi3SetString` (FMI 3.0) of `", stringify!($model), "`: refused (it has no String variables).")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "`instance` is a live instance or null."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3SetString(instance: $crate::fmi3::types::fmi3Instance, _vr: *const ::std::ffi::c_void, _nvr: usize, _values: *const ::std::ffi::c_void, _n: usize) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::unsupported::<$model>(instance, "fmi3SetString", "it has no String variables") }
        }
        #[doc = concat!("`fmi3GetBinary` (FMI 3.0) of `", stringify!($model), "`: refused (it has no Binary variables).")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "`instance` is a live instance or null."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3GetBinary(instance: $crate::fmi3::types::fmi3Instance, _vr: *const ::std::ffi::c_void, _nvr: usize, _sizes: *mut ::std::ffi::c_void, _values: *mut ::std::ffi::c_void, _n: usize) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::unsupported::<$model>(instance, "fmi3GetBinary", "it has no Binary variables") }
        }
        #[doc = concat!("`fmi3SetBinary` (FMI 3.0) of `", stringify!($model), "`: refused (it has no Binary variables).")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "`instance` is a live instance or null."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3SetBinary(instance: $crate::fmi3::types::fmi3Instance, _vr: *const ::std::ffi::c_void, _nvr: usize, _sizes: *const ::std::ffi::c_void, _values: *const ::std::ffi::c_void, _n: usize) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::unsupported::<$model>(instance, "fmi3SetBinary", "it has no Binary variables") }
        }
        #[doc = concat!("`fmi3GetClock` (FMI 3.0) of `", stringify!($model), "`: refused (it has no clocks).")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "`instance` is a live instance or null."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3GetClock(instance: $crate::fmi3::types::fmi3Instance, _vr: *const ::std::ffi::c_void, _nvr: usize, _values: *mut ::std::ffi::c_void) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::unsupported::<$model>(instance, "fmi3GetClock", "it has no clocks") }
        }
        #[doc = concat!("`fmi3SetClock` (FMI 3.0) of `", stringify!($model), "`: refused (it has no clocks).")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "`instance` is a live instance or null."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3SetClock(instance: $crate::fmi3::types::fmi3Instance, _vr: *const ::std::ffi::c_void, _nvr: usize, _values: *const ::std::ffi::c_void) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::unsupported::<$model>(instance, "fmi3SetClock", "it has no clocks") }
        }
        #[doc = concat!("`fmi3GetNumberOfVariableDependencies` (FMI 3.0) of `", stringify!($model), "`: refused (providesPerElementDependencies='false').")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "`instance` is a live instance or null."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3GetNumberOfVariableDependencies(instance: $crate::fmi3::types::fmi3Instance, _vr: u32, _n: *mut ::std::ffi::c_void) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::unsupported::<$model>(instance, "fmi3GetNumberOfVariableDependencies", "providesPerElementDependencies=\"false\"") }
        }
        #[doc = concat!("`fmi3GetVariableDependencies` (FMI 3.0) of `", stringify!($model), "`: refused (providesPerElementDependencies='false').")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "`instance` is a live instance or null."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3GetVariableDependencies(instance: $crate::fmi3::types::fmi3Instance, _vr: u32, _ei: *mut ::std::ffi::c_void, _ind: *mut ::std::ffi::c_void, _eii: *mut ::std::ffi::c_void, _kinds: *mut ::std::ffi::c_void, _n: usize) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::unsupported::<$model>(instance, "fmi3GetVariableDependencies", "providesPerElementDependencies=\"false\"") }
        }
        #[doc = concat!("`fmi3GetDirectionalDerivative` (FMI 3.0) of `", stringify!($model), "`: refused (providesDirectionalDerivatives='false').")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "`instance` is a live instance or null."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3GetDirectionalDerivative(instance: $crate::fmi3::types::fmi3Instance, _u: *const ::std::ffi::c_void, _nu: usize, _k: *const ::std::ffi::c_void, _nk: usize, _seed: *const ::std::ffi::c_void, _ns: usize, _sens: *mut ::std::ffi::c_void, _nsens: usize) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::unsupported::<$model>(instance, "fmi3GetDirectionalDerivative", "providesDirectionalDerivatives=\"false\"") }
        }
        #[doc = concat!("`fmi3GetAdjointDerivative` (FMI 3.0) of `", stringify!($model), "`: refused (providesAdjointDerivatives='false').")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "`instance` is a live instance or null."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3GetAdjointDerivative(instance: $crate::fmi3::types::fmi3Instance, _u: *const ::std::ffi::c_void, _nu: usize, _k: *const ::std::ffi::c_void, _nk: usize, _seed: *const ::std::ffi::c_void, _ns: usize, _sens: *mut ::std::ffi::c_void, _nsens: usize) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::unsupported::<$model>(instance, "fmi3GetAdjointDerivative", "providesAdjointDerivatives=\"false\"") }
        }
        #[doc = concat!("`fmi3EnterConfigurationMode` (FMI 3.0) of `", stringify!($model), "`: refused (it has no structural parameters).")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "`instance` is a live instance or null."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3EnterConfigurationMode(instance: $crate::fmi3::types::fmi3Instance) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::unsupported::<$model>(instance, "fmi3EnterConfigurationMode", "it has no structural parameters") }
        }
        #[doc = concat!("`fmi3ExitConfigurationMode` (FMI 3.0) of `", stringify!($model), "`: refused (it has no structural parameters).")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "`instance` is a live instance or null."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3ExitConfigurationMode(instance: $crate::fmi3::types::fmi3Instance) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::unsupported::<$model>(instance, "fmi3ExitConfigurationMode", "it has no structural parameters") }
        }
        #[doc = concat!("`fmi3GetIntervalDecimal` (FMI 3.0) of `", stringify!($model), "`: refused (it has no clocks).")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "`instance` is a live instance or null."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3GetIntervalDecimal(instance: $crate::fmi3::types::fmi3Instance, _vr: *const ::std::ffi::c_void, _nvr: usize, _i: *mut ::std::ffi::c_void, _q: *mut ::std::ffi::c_void) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::unsupported::<$model>(instance, "fmi3GetIntervalDecimal", "it has no clocks") }
        }
        #[doc = concat!("`fmi3GetIntervalFraction` (FMI 3.0) of `", stringify!($model), "`: refused (it has no clocks).")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "`instance` is a live instance or null."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3GetIntervalFraction(instance: $crate::fmi3::types::fmi3Instance, _vr: *const ::std::ffi::c_void, _nvr: usize, _c: *mut ::std::ffi::c_void, _r: *mut ::std::ffi::c_void, _q: *mut ::std::ffi::c_void) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::unsupported::<$model>(instance, "fmi3GetIntervalFraction", "it has no clocks") }
        }
        #[doc = concat!("`fmi3GetShiftDecimal` (FMI 3.0) of `", stringify!($model), "`: refused (it has no clocks).")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "`instance` is a live instance or null."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3GetShiftDecimal(instance: $crate::fmi3::types::fmi3Instance, _vr: *const ::std::ffi::c_void, _nvr: usize, _s: *mut ::std::ffi::c_void) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::unsupported::<$model>(instance, "fmi3GetShiftDecimal", "it has no clocks") }
        }
        #[doc = concat!("`fmi3GetShiftFraction` (FMI 3.0) of `", stringify!($model), "`: refused (it has no clocks).")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "`instance` is a live instance or null."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3GetShiftFraction(instance: $crate::fmi3::types::fmi3Instance, _vr: *const ::std::ffi::c_void, _nvr: usize, _c: *mut ::std::ffi::c_void, _r: *mut ::std::ffi::c_void) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::unsupported::<$model>(instance, "fmi3GetShiftFraction", "it has no clocks") }
        }
        #[doc = concat!("`fmi3SetIntervalDecimal` (FMI 3.0) of `", stringify!($model), "`: refused (it has no clocks).")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "`instance` is a live instance or null."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3SetIntervalDecimal(instance: $crate::fmi3::types::fmi3Instance, _vr: *const ::std::ffi::c_void, _nvr: usize, _i: *const ::std::ffi::c_void) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::unsupported::<$model>(instance, "fmi3SetIntervalDecimal", "it has no clocks") }
        }
        #[doc = concat!("`fmi3SetIntervalFraction` (FMI 3.0) of `", stringify!($model), "`: refused (it has no clocks).")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "`instance` is a live instance or null."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3SetIntervalFraction(instance: $crate::fmi3::types::fmi3Instance, _vr: *const ::std::ffi::c_void, _nvr: usize, _c: *const ::std::ffi::c_void, _r: *const ::std::ffi::c_void) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::unsupported::<$model>(instance, "fmi3SetIntervalFraction", "it has no clocks") }
        }
        #[doc = concat!("`fmi3SetShiftDecimal` (FMI 3.0) of `", stringify!($model), "`: refused (it has no clocks).")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "`instance` is a live instance or null."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3SetShiftDecimal(instance: $crate::fmi3::types::fmi3Instance, _vr: *const ::std::ffi::c_void, _nvr: usize, _s: *const ::std::ffi::c_void) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::unsupported::<$model>(instance, "fmi3SetShiftDecimal", "it has no clocks") }
        }
        #[doc = concat!("`fmi3SetShiftFraction` (FMI 3.0) of `", stringify!($model), "`: refused (it has no clocks).")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "`instance` is a live instance or null."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3SetShiftFraction(instance: $crate::fmi3::types::fmi3Instance, _vr: *const ::std::ffi::c_void, _nvr: usize, _c: *const ::std::ffi::c_void, _r: *const ::std::ffi::c_void) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::unsupported::<$model>(instance, "fmi3SetShiftFraction", "it has no clocks") }
        }
        #[doc = concat!("`fmi3EvaluateDiscreteStates` (FMI 3.0) of `", stringify!($model), "`: refused (providesEvaluateDiscreteStates='false').")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "`instance` is a live instance or null."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3EvaluateDiscreteStates(instance: $crate::fmi3::types::fmi3Instance) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::unsupported::<$model>(instance, "fmi3EvaluateDiscreteStates", "providesEvaluateDiscreteStates=\"false\"") }
        }
        #[doc = concat!("`fmi3UpdateDiscreteStates` (FMI 3.0) of `", stringify!($model), "`: apply the inputs set in Event Mode.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 3.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3UpdateDiscreteStates(instance: $crate::fmi3::types::fmi3Instance, discreteStatesNeedUpdate: *mut bool, terminateSimulation: *mut bool, nominalsOfContinuousStatesChanged: *mut bool, valuesOfContinuousStatesChanged: *mut bool, nextEventTimeDefined: *mut bool, nextEventTime: *mut f64) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::fmi3UpdateDiscreteStates::<$model>(instance, discreteStatesNeedUpdate, terminateSimulation, nominalsOfContinuousStatesChanged, valuesOfContinuousStatesChanged, nextEventTimeDefined, nextEventTime) }
        }
        #[doc = concat!("`fmi3EnterContinuousTimeMode` (FMI 3.0) of `", stringify!($model), "`: refused (Co-Simulation only).")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "`instance` is a live instance or null."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3EnterContinuousTimeMode(instance: $crate::fmi3::types::fmi3Instance) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::unsupported::<$model>(instance, "fmi3EnterContinuousTimeMode", "Co-Simulation only") }
        }
        #[doc = concat!("`fmi3CompletedIntegratorStep` (FMI 3.0) of `", stringify!($model), "`: refused (Co-Simulation only).")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "`instance` is a live instance or null."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3CompletedIntegratorStep(instance: $crate::fmi3::types::fmi3Instance, _no: bool, _enter: *mut bool, _term: *mut bool) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::unsupported::<$model>(instance, "fmi3CompletedIntegratorStep", "Co-Simulation only") }
        }
        #[doc = concat!("`fmi3SetTime` (FMI 3.0) of `", stringify!($model), "`: refused (Co-Simulation only).")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "`instance` is a live instance or null."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3SetTime(instance: $crate::fmi3::types::fmi3Instance, _time: f64) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::unsupported::<$model>(instance, "fmi3SetTime", "Co-Simulation only") }
        }
        #[doc = concat!("`fmi3SetContinuousStates` (FMI 3.0) of `", stringify!($model), "`: refused (Co-Simulation only).")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "`instance` is a live instance or null."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3SetContinuousStates(instance: $crate::fmi3::types::fmi3Instance, _x: *const ::std::ffi::c_void, _nx: usize) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::unsupported::<$model>(instance, "fmi3SetContinuousStates", "Co-Simulation only") }
        }
        #[doc = concat!("`fmi3GetContinuousStateDerivatives` (FMI 3.0) of `", stringify!($model), "`: refused (Co-Simulation only).")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "`instance` is a live instance or null."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3GetContinuousStateDerivatives(instance: $crate::fmi3::types::fmi3Instance, _d: *mut ::std::ffi::c_void, _nx: usize) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::unsupported::<$model>(instance, "fmi3GetContinuousStateDerivatives", "Co-Simulation only") }
        }
        #[doc = concat!("`fmi3GetEventIndicators` (FMI 3.0) of `", stringify!($model), "`: refused (Co-Simulation only).")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "`instance` is a live instance or null."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3GetEventIndicators(instance: $crate::fmi3::types::fmi3Instance, _e: *mut ::std::ffi::c_void, _ni: usize) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::unsupported::<$model>(instance, "fmi3GetEventIndicators", "Co-Simulation only") }
        }
        #[doc = concat!("`fmi3GetContinuousStates` (FMI 3.0) of `", stringify!($model), "`: refused (Co-Simulation only).")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "`instance` is a live instance or null."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3GetContinuousStates(instance: $crate::fmi3::types::fmi3Instance, _x: *mut ::std::ffi::c_void, _nx: usize) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::unsupported::<$model>(instance, "fmi3GetContinuousStates", "Co-Simulation only") }
        }
        #[doc = concat!("`fmi3GetNominalsOfContinuousStates` (FMI 3.0) of `", stringify!($model), "`: refused (Co-Simulation only).")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "`instance` is a live instance or null."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3GetNominalsOfContinuousStates(instance: $crate::fmi3::types::fmi3Instance, _n: *mut ::std::ffi::c_void, _nx: usize) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::unsupported::<$model>(instance, "fmi3GetNominalsOfContinuousStates", "Co-Simulation only") }
        }
        #[doc = concat!("`fmi3GetNumberOfEventIndicators` (FMI 3.0) of `", stringify!($model), "`: refused (Co-Simulation only).")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "`instance` is a live instance or null."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3GetNumberOfEventIndicators(instance: $crate::fmi3::types::fmi3Instance, _n: *mut ::std::ffi::c_void) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::unsupported::<$model>(instance, "fmi3GetNumberOfEventIndicators", "Co-Simulation only") }
        }
        #[doc = concat!("`fmi3GetNumberOfContinuousStates` (FMI 3.0) of `", stringify!($model), "`: refused (Co-Simulation only).")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "`instance` is a live instance or null."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3GetNumberOfContinuousStates(instance: $crate::fmi3::types::fmi3Instance, _n: *mut ::std::ffi::c_void) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::unsupported::<$model>(instance, "fmi3GetNumberOfContinuousStates", "Co-Simulation only") }
        }
        #[doc = concat!("`fmi3GetOutputDerivatives` (FMI 3.0) of `", stringify!($model), "`: refused (maxOutputDerivativeOrder='0').")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "`instance` is a live instance or null."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3GetOutputDerivatives(instance: $crate::fmi3::types::fmi3Instance, _vr: *const ::std::ffi::c_void, _nvr: usize, _orders: *const ::std::ffi::c_void, _values: *mut ::std::ffi::c_void, _n: usize) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::unsupported::<$model>(instance, "fmi3GetOutputDerivatives", "maxOutputDerivativeOrder=\"0\"") }
        }
        #[doc = concat!("`fmi3ActivateModelPartition` (FMI 3.0) of `", stringify!($model), "`: refused (Co-Simulation only).")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "`instance` is a live instance or null."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi3ActivateModelPartition(instance: $crate::fmi3::types::fmi3Instance, _clock: u32, _t: f64) -> $crate::fmi3::types::fmi3Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi3::functions::unsupported::<$model>(instance, "fmi3ActivateModelPartition", "Co-Simulation only") }
        }
    };
}
