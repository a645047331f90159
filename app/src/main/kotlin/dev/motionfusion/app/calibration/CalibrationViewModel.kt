package dev.motionfusion.app.calibration

import dev.motionfusion.app.R
import androidx.annotation.StringRes
import androidx.lifecycle.ViewModel
import androidx.lifecycle.viewModelScope
import dev.motionfusion.core.Vector3
import dev.motionfusion.core.calib.AccelerometerCalibration
import dev.motionfusion.core.calib.Calibration
import dev.motionfusion.core.calib.CalibrationSettings
import dev.motionfusion.core.calib.Calibrator
import dev.motionfusion.core.calib.DirectionCoverage
import dev.motionfusion.core.calib.Fit
import dev.motionfusion.core.calib.GyroscopeCalibration
import dev.motionfusion.core.calib.MagnetometerCalibration
import dev.motionfusion.core.calib.MagnetometerFitter
import dev.motionfusion.core.calib.StillPeriods
import dev.motionfusion.core.event.SessionStream
import kotlinx.coroutines.CoroutineDispatcher
import kotlinx.coroutines.Job
import kotlinx.coroutines.cancelAndJoin
import kotlinx.coroutines.flow.MutableStateFlow
import kotlinx.coroutines.flow.StateFlow
import kotlinx.coroutines.flow.asStateFlow
import kotlinx.coroutines.flow.update
import kotlinx.coroutines.launch
import java.io.IOException

/** The parts of the calibration screen: the two guided fits, and the still recording for `fusion allan`. */
enum class CalibrationStep { MAGNETOMETER, POSES, STILL }

/** Where a step is: not started, collecting readings, fitted (accepted or refused). */
enum class CalibrationStage { READY, COLLECTING, RESULT }

/**
 * The six faces the accelerometer step asks for, by the device axis that points up (the
 * accelerometer then reads +g on it): screen up is +z, standing on the bottom edge +y, lying on
 * the left edge +x.
 */
enum class PoseFace(val axis: Int, val sign: Int) {
    SCREEN_UP(2, 1), SCREEN_DOWN(2, -1), BOTTOM_EDGE_DOWN(1, 1), TOP_EDGE_DOWN(1, -1), LEFT_EDGE_DOWN(0, 1), RIGHT_EDGE_DOWN(0, -1);

    companion object {
        /** The face whose up axis is within 25° of the specific force [g], or null (a corner). */
        fun of(g: Vector3): PoseFace? {
            val n = g.norm()
            if (!(n > 0.0)) return null
            return entries.firstOrNull { g[it.axis] * it.sign > COS_25 * n }
        }

        private val COS_25 = kotlin.math.cos(Math.toRadians(25.0))
    }
}

/**
 * What the calibration screen shows. Coverage: [cellHits] per cell of core's
 * [DirectionCoverage] grid (band-major), [coverage] the fraction covered. Poses: [facesHeld]
 * (six faces) and [poses] (all distinct poses, corners included).
 */
data class CalibrationUiState(
    val step: CalibrationStep = CalibrationStep.MAGNETOMETER,
    val stage: CalibrationStage = CalibrationStage.READY,
    /** Why the step cannot run on this device (a sensor it needs is missing), or null. */
    /** Why the step cannot run here (a string resource), or null. */
    @StringRes val unavailable: Int? = null,
    val magStream: SessionStream? = null,
    val cellHits: List<Int> = List(DirectionCoverage.CELLS) { 0 },
    val coverage: Double = 0.0,
    val minCoverage: Double = CalibrationSettings().minCoverage,
    val magSamples: Long = 0,
    val elapsedS: Double = 0.0,
    val magFit: Fit<MagnetometerCalibration>? = null,
    val facesHeld: Set<PoseFace> = emptySet(),
    val poses: Int = 0,
    val still: Boolean = false,
    val holdS: Double = 0.0,
    val minPoseS: Double = CalibrationSettings().minPoseS,
    val accFit: Fit<AccelerometerCalibration>? = null,
    val gyroFit: Fit<GyroscopeCalibration>? = null,
    val saved: Boolean = false,
    val saveError: String? = null,
) {
    /** The face to put the phone on next, or null when all six are held. */
    val askedFace: PoseFace? get() = PoseFace.entries.firstOrNull { it !in facesHeld }

    /** "Pose k of 6": the asked face's number, 7 when all are held. */
    val poseNumber: Int get() = facesHeld.size + 1

    /** Results of this step that may be stored. */
    val hasAccepted: Boolean get() = when (step) {
        CalibrationStep.MAGNETOMETER -> magFit is Fit.Done
        CalibrationStep.POSES -> accFit is Fit.Done || gyroFit is Fit.Done
        CalibrationStep.STILL -> false
    }
}

/**
 * The guided calibration: feeds [source]'s readings to core's fitters (MagnetometerFitter for
 * the turn-through, StillPeriods for the poses and the gyroscope bias) on [compute], publishes
 * a [CalibrationUiState] a few times a second of sensor time, fits on [finish] and stores the
 * accepted results in [store] on [io]. All the math is fusion-core's.
 */
class CalibrationViewModel(
    private val source: CalibrationSampleSource,
    private val store: CalibrationStore,
    private val settings: CalibrationSettings,
    private val compute: CoroutineDispatcher,
    private val io: CoroutineDispatcher,
    private val madeBy: String,
) : ViewModel() {
    private val streams = source.streams
    private val magStream = Calibrator.magnetometerStream(streams)
    private val gyroStream = Calibrator.gyroscopeStream(streams)
    private val state0 = CalibrationUiState(minCoverage = settings.minCoverage, minPoseS = settings.minPoseS, magStream = magStream)
    private val _state = MutableStateFlow(state0.copy(unavailable = unavailable(CalibrationStep.MAGNETOMETER)))
    val state: StateFlow<CalibrationUiState> = _state.asStateFlow()

    private var job: Job? = null
    private var mag: MagnetometerFitter? = null
    private var still: StillPeriods? = null
    /** The clock stream's first timestamp of this collection (kept through a pause), ns. */
    private var firstNs = Long.MIN_VALUE
    /** The collection is paused ([pause]): its readings are kept, [resume] goes on with them. */
    private var paused = false

    private fun unavailable(step: CalibrationStep): Int? = when (step) {
        CalibrationStep.MAGNETOMETER -> if (magStream == null) R.string.calibration_no_magnetometer else null
        CalibrationStep.POSES -> when {
            SessionStream.ACCELEROMETER !in streams -> R.string.calibration_no_accelerometer
            gyroStream == null -> R.string.calibration_no_gyroscope
            else -> null
        }
        CalibrationStep.STILL -> if (SessionStream.ACCELEROMETER !in streams && gyroStream == null) R.string.calibration_no_acc_gyro else null
    }

    /** Shows [step], not started; stops a collection in progress. */
    fun select(step: CalibrationStep) {
        if (step == _state.value.step && _state.value.stage == CalibrationStage.READY) return
        job?.cancel()
        job = null
        paused = false
        _state.value = state0.copy(step = step, unavailable = unavailable(step))
    }

    /**
     * The screen went away (turned off, another app): the sensors are let go, but what was collected
     * is kept, and the step stays where it was; [resume] goes on from there.
     */
    fun pause() {
        if (_state.value.stage != CalibrationStage.COLLECTING || paused) return
        paused = true
        // Kept, cancelled: the next collection (or the fit) waits for it to end, so the fitter is fed by one at a time.
        job?.cancel()
    }

    /** The screen is back: a paused collection goes on with the readings it had. */
    fun resume() {
        if (!paused) return
        paused = false
        if (_state.value.stage != CalibrationStage.COLLECTING) return
        val previous = job
        job = if (_state.value.step == CalibrationStep.MAGNETOMETER) collectMagnetometer(mag!!, previous) else collectPoses(still!!, previous)
    }

    /** Starts collecting for the current step (again from nothing); the still recording is the recording service's. */
    fun start() {
        val s = _state.value
        if (s.unavailable != null || s.stage == CalibrationStage.COLLECTING || s.step == CalibrationStep.STILL) return
        job?.cancel()
        paused = false
        firstNs = Long.MIN_VALUE
        _state.value = state0.copy(step = s.step, stage = CalibrationStage.COLLECTING)
        job = if (s.step == CalibrationStep.MAGNETOMETER) {
            collectMagnetometer(MagnetometerFitter(settings, magStream!!).also { mag = it })
        } else {
            collectPoses(StillPeriods(settings, gyroStream!!).also { still = it })
        }
    }

    private fun collectMagnetometer(fitter: MagnetometerFitter, after: Job? = null): Job {
        return collect(magStream!!, after, { r -> if (r.stream == magStream) fitter.add(r.x, r.y, r.z) }) { elapsed ->
            val c = fitter.coverage()
            _state.update {
                it.copy(cellHits = List(DirectionCoverage.CELLS) { i -> c.hits(i) }, coverage = c.fraction, magSamples = fitter.samples, elapsedS = elapsed)
            }
        }
    }

    private fun collectPoses(periods: StillPeriods, after: Job? = null): Job {
        val feed = { r: CalibrationSample ->
            when (r.stream) {
                SessionStream.ACCELEROMETER -> periods.accelerometer(r.x, r.y, r.z)
                gyroStream -> periods.gyroscope(r.timestampNs, r.x, r.y, r.z)
                else -> Unit
            }
        }
        return collect(gyroStream!!, after, feed) { elapsed ->
            val poses = periods.distinctPoses()
            _state.update {
                it.copy(
                    facesHeld = poses.mapNotNullTo(LinkedHashSet()) { g -> PoseFace.of(g) }, poses = poses.size,
                    still = periods.lastWindowStill, holdS = periods.currentPoseS, elapsedS = elapsed,
                )
            }
        }
    }

    /**
     * Collects [source] on [compute], handing every reading to [feed]; every [PUBLISH_NS] of
     * [clock]'s timestamps (and when they step back) calls [publish] with the seconds since
     * [clock]'s first reading (of the collection, kept through a pause); [after] (a paused one) ends first.
     */
    private fun collect(clock: SessionStream, after: Job?, feed: (CalibrationSample) -> Unit, publish: (Double) -> Unit): Job = viewModelScope.launch(compute) {
        after?.join()
        var published = Long.MIN_VALUE
        source.samples().collect { r ->
            feed(r)
            if (r.stream != clock) return@collect
            val t = r.timestampNs
            if (firstNs == Long.MIN_VALUE) firstNs = t
            if (published == Long.MIN_VALUE || t - published >= PUBLISH_NS || t < published) {
                published = t
                publish((t - firstNs) * 1e-9)
            }
        }
    }

    /** Stops collecting and fits what was collected. */
    fun finish() {
        if (_state.value.stage != CalibrationStage.COLLECTING) return
        val collecting = job
        paused = false
        job = viewModelScope.launch(compute) {
            collecting?.cancelAndJoin()
            when (_state.value.step) {
                CalibrationStep.MAGNETOMETER -> {
                    val f = mag!!
                    val fit = f.fit()
                    val c = f.coverage()
                    _state.update {
                        it.copy(stage = CalibrationStage.RESULT, magFit = fit, magSamples = f.samples,
                            cellHits = List(DirectionCoverage.CELLS) { i -> c.hits(i) }, coverage = (fit.valueOrNull()?.coverage ?: c.fraction))
                    }
                }
                CalibrationStep.POSES, CalibrationStep.STILL -> {
                    val p = still!!
                    val acc = p.accelerometerFit()
                    val gyro = p.gyroscopeFit()
                    _state.update { it.copy(stage = CalibrationStage.RESULT, accFit = acc, gyroFit = gyro, still = false, holdS = 0.0) }
                }
            }
        }
    }

    /** Stores this step's accepted fits for the device (the refused ones are not stored). */
    fun save() {
        val s = _state.value
        if (s.stage != CalibrationStage.RESULT || !s.hasAccepted || s.saved) return
        val fitted = Calibration(
            magnetometer = s.magFit?.valueOrNull(), gyroscope = s.gyroFit?.valueOrNull(), accelerometer = s.accFit?.valueOrNull(), source = madeBy,
        )
        viewModelScope.launch(io) {
            try {
                store.accept(fitted)
                _state.update { it.copy(saved = true, saveError = null) }
            } catch (e: IOException) {
                _state.update { it.copy(saveError = store.problem ?: e.toString()) }
            }
        }
    }

    private companion object {
        /** State is published every 0.2 s of sensor time: the coverage costs a fit over the readings kept. */
        const val PUBLISH_NS = 200_000_000L
    }
}

