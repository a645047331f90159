/*
 * Sample gating: which samples reach the filter's steps, and the counts of those that do not.
 *
 * Validation: a sample with a non-finite axis, an axis beyond any phone's range (SensorRanges) or, for the
 * accelerometer and magnetometer, zero length is dropped and counted; a held reading so dropped becomes
 * "none" (the next steps run without it). A field stronger than the earth's is no heading: held as none too.
 *
 * Pairing rule. Android delivers each sensor on its own. The gate holds the latest accelerometer and
 * magnetometer sample; the filter steps on each gyroscope sample, over the time since the previous
 * gyroscope sample, with the held samples if they are no older than maxGap (else counted stale).
 *
 * Start (Initialisation.FIRST_SAMPLE): the first gyroscope sample with a fresh accelerometer sample, and in
 * MARG mode a magnetometer sample too, waited for at most maxGap after the first accelerometer sample.
 * Gaps: a timestamp that does not advance, or a gap longer than maxGap, is counted and not integrated; the
 * step after such a gap is flagged (the phone may have turned any way meanwhile: the filter recovers as
 * after a saturated reading).
 * Saturation: a gyroscope axis at or beyond gyroSaturation is flagged for the step and counted.
 * Timestamps ns, readings SI (rad/s, m/s², µT). Allocation-free.
 */
package dev.motionfusion.core.filter

import kotlin.math.abs

/** What the gate makes of a gyroscope sample. */
internal enum class Admission {
    /** Dropped (invalid, before the start, not advancing, after a gap); counted. */
    SKIP,

    /** The filter starts at this sample (it integrates nothing). */
    START,

    /** A step: [Step.dt], the gyroscope reading and the readings' freshness are set. */
    STEP,
}

internal class SampleGate(settings: FilterSettings, private val s: Step) : Stage<SampleGate.State> {
    private val marg = settings.mode == FilterMode.MARG
    private val waitsForSample = settings.initialisation == Initialisation.FIRST_SAMPLE
    private val maxGapNs = (settings.maxGap * 1e9).toLong()
    private val gyroSaturation = settings.gyroSaturation ?: 0.0
    private val saturationOn = settings.gyroSaturation != null

    // The held readings' times and whether they are usable (the readings themselves are in the Step).
    private var accT = 0L
    private var hasAcc = false
    private var magT = 0L
    private var hasMag = false
    private var magTooStrong = false

    private var initialised = false
    private var lastT = 0L
    private var firstAccT = 0L
    private var waitingForMag = false

    /** The counts of FilterDiagnostics that the gate makes. */
    var steps = 0L
        private set
    var skippedBeforeInit = 0L
        private set
    var skippedNonFinite = 0L
        private set
    var skippedOutOfRange = 0L
        private set
    var skippedZero = 0L
        private set
    var skippedTimestamp = 0L
        private set
    var skippedGap = 0L
        private set
    var staleSamples = 0L
        private set

    /** Steps whose fresh magnetometer reading was left out as stronger than any earth field. */
    var tooStrong = 0L
        private set
    var saturations = 0L
        private set

    /** The last step's gyroscope reading was saturated (gyroSaturation). */
    var saturated = false
        private set

    /** The last step is the first after a gap longer than maxGap (its rotation unknown). */
    var afterGap = false
        private set

    // A gap was skipped and no step has followed it yet.
    private var gapPending = false

    val isInitialised: Boolean get() = initialised

    /** The held magnetometer reading is stronger than any earth field (and so left out). */
    val magneticTooStrong: Boolean get() = magTooStrong

    fun holdAccelerometer(t: Long, x: Double, y: Double, z: Double) {
        hasAcc = valid(x, y, z, SensorRanges.ACCELEROMETER_M_S2)
        s.ax = x; s.ay = y; s.az = z; accT = t
    }

    /** Ignored in IMU mode. */
    fun holdMagnetometer(t: Long, x: Double, y: Double, z: Double) {
        if (!marg) return
        hasMag = valid(x, y, z, SensorRanges.MAGNETOMETER_UT)
        // A field stronger than the earth's is no heading (a magnet, or a raw reading with its hard-iron offset).
        magTooStrong = hasMag && !SensorRanges.isEarthField(x, y, z)
        if (magTooStrong) hasMag = false
        s.mx = x; s.my = y; s.mz = z; magT = t
    }

    /** A table row without magnetometer: no magnetometer reading held. */
    fun dropMagnetometer() {
        hasMag = false
        magTooStrong = false
    }

    /** A gyroscope sample ([x], [y], [z] rad/s at [t] ns): validation, pairing, start, timing. */
    fun admit(t: Long, x: Double, y: Double, z: Double): Admission {
        if (!(x.isFinite() && y.isFinite() && z.isFinite())) {
            skippedNonFinite++
            return Admission.SKIP
        }
        if (abs(x) > SensorRanges.GYROSCOPE_RAD_S || abs(y) > SensorRanges.GYROSCOPE_RAD_S || abs(z) > SensorRanges.GYROSCOPE_RAD_S) {
            skippedOutOfRange++
            return Admission.SKIP
        }
        s.accOk = hasAcc && fresh(t, accT)
        s.magOk = hasMag && fresh(t, magT)
        s.magFresh = (hasMag || magTooStrong) && fresh(t, magT)
        if (!initialised) return if (mayStart(t)) Admission.START else Admission.SKIP
        if (t <= lastT) {
            skippedTimestamp++
            lastT = minOf(lastT, t)
            return Admission.SKIP
        }
        val gapNs = t - lastT
        lastT = t
        if (gapNs > maxGapNs) {
            skippedGap++
            gapPending = true
            return Admission.SKIP
        }
        afterGap = gapPending
        gapPending = false
        s.dt = gapNs * 1e-9
        s.gx = x; s.gy = y; s.gz = z
        steps++
        if ((hasAcc && !s.accOk) || (hasMag && !s.magOk)) staleSamples++
        if (magTooStrong && fresh(t, magT)) tooStrong++
        saturated = saturationOn && (abs(x) >= gyroSaturation || abs(y) >= gyroSaturation || abs(z) >= gyroSaturation)
        if (saturated) saturations++
        return Admission.STEP
    }

    /** The filter started at [t] (its orientation set). */
    fun started(t: Long) {
        initialised = true
        lastT = t
    }

    /**
     * For a pass backward in time (MadgwickFilter.turnAround): [t] is the time, on the new pass's clock, of
     * the last step taken; the held readings keep their age then.
     */
    fun turnAround(t: Long) {
        accT = t - (lastT - accT)
        magT = t - (lastT - magT)
        lastT = t
        firstAccT = t
    }

    /** Initialisation.IDENTITY: at once; FIRST_SAMPLE: with a fresh accelerometer (and magnetometer, see the header). */
    private fun mayStart(t: Long): Boolean {
        if (!waitsForSample) return true
        if (!s.accOk) {
            skippedBeforeInit++
            return false
        }
        if (marg && !s.magOk) {
            if (!waitingForMag) {
                waitingForMag = true
                firstAccT = t
            }
            if (t - firstAccT <= maxGapNs) {
                skippedBeforeInit++
                return false
            }
        }
        return true
    }

    private fun fresh(t: Long, sampleT: Long): Boolean = t - sampleT <= maxGapNs

    private fun valid(x: Double, y: Double, z: Double, limit: Double): Boolean {
        if (!(x.isFinite() && y.isFinite() && z.isFinite())) {
            skippedNonFinite++
            return false
        }
        if (abs(x) > limit || abs(y) > limit || abs(z) > limit) {
            skippedOutOfRange++
            return false
        }
        if (x == 0.0 && y == 0.0 && z == 0.0) {
            skippedZero++
            return false
        }
        return true
    }

    /** The held readings, their times and flags, the clock and the counts. */
    data class State(
        val ax: Double, val ay: Double, val az: Double, val accT: Long, val hasAcc: Boolean,
        val mx: Double, val my: Double, val mz: Double, val magT: Long, val hasMag: Boolean, val magTooStrong: Boolean,
        val initialised: Boolean, val lastT: Long, val firstAccT: Long, val waitingForMag: Boolean,
        val steps: Long, val skippedBeforeInit: Long, val skippedNonFinite: Long, val skippedOutOfRange: Long,
        val skippedZero: Long, val skippedTimestamp: Long, val skippedGap: Long, val staleSamples: Long,
        val tooStrong: Long, val saturations: Long, val saturated: Boolean, val afterGap: Boolean, val gapPending: Boolean,
    )

    override fun state() = State(
        s.ax, s.ay, s.az, accT, hasAcc, s.mx, s.my, s.mz, magT, hasMag, magTooStrong,
        initialised, lastT, firstAccT, waitingForMag,
        steps, skippedBeforeInit, skippedNonFinite, skippedOutOfRange, skippedZero, skippedTimestamp, skippedGap, staleSamples,
        tooStrong, saturations, saturated, afterGap, gapPending,
    )

    override fun restore(state: State) = with(state) {
        s.ax = ax; s.ay = ay; s.az = az; this@SampleGate.accT = accT; this@SampleGate.hasAcc = hasAcc
        s.mx = mx; s.my = my; s.mz = mz; this@SampleGate.magT = magT; this@SampleGate.hasMag = hasMag
        this@SampleGate.magTooStrong = magTooStrong
        this@SampleGate.initialised = initialised; this@SampleGate.lastT = lastT
        this@SampleGate.firstAccT = firstAccT; this@SampleGate.waitingForMag = waitingForMag
        this@SampleGate.steps = steps; this@SampleGate.skippedBeforeInit = skippedBeforeInit
        this@SampleGate.skippedNonFinite = skippedNonFinite; this@SampleGate.skippedOutOfRange = skippedOutOfRange
        this@SampleGate.skippedZero = skippedZero; this@SampleGate.skippedTimestamp = skippedTimestamp
        this@SampleGate.skippedGap = skippedGap; this@SampleGate.staleSamples = staleSamples
        this@SampleGate.tooStrong = tooStrong; this@SampleGate.saturations = saturations; this@SampleGate.saturated = saturated
        this@SampleGate.afterGap = afterGap; this@SampleGate.gapPending = gapPending
    }

    override fun reset() = restore(NEW)

    private companion object {
        val NEW = State(
            0.0, 0.0, 0.0, 0L, false, 0.0, 0.0, 0.0, 0L, false, false,
            false, 0L, 0L, false,
            0L, 0L, 0L, 0L, 0L, 0L, 0L, 0L, 0L, 0L, false, false, false,
        )
    }
}
