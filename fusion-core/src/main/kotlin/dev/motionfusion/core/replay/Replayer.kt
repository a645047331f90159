/*
 * Replay: runs the Madgwick filter over recorded events in time order, as the app would have
 * live. Accelerometer and magnetometer samples are held; each gyroscope sample is one filter
 * step and one output step (the filter's pairing rule, filter/SampleGate.kt). Orientation sensor → ENU,
 * quaternions [w, x, y, z] Hamilton; timestamps ns, times s relative to the recording's origin.
 */
package dev.motionfusion.core.replay

import dev.motionfusion.core.filter.FilterMode
import dev.motionfusion.core.filter.FilterSettings
import dev.motionfusion.core.filter.MadgwickFilter
import dev.motionfusion.core.filter.SensorRanges
import dev.motionfusion.core.filter.offline.FieldPersistence
import dev.motionfusion.core.filter.offline.OfflineOutput
import dev.motionfusion.core.filter.offline.OfflinePasses
import dev.motionfusion.core.filter.offline.OfflineSettings
import dev.motionfusion.core.io.DataFormatException
import dev.motionfusion.core.WorldFrame
import dev.motionfusion.core.event.RowEvents
import dev.motionfusion.core.input.ImuTableReader
import dev.motionfusion.core.event.SensorEvents
import dev.motionfusion.core.event.SessionStream
import kotlin.math.abs

/** The state after one gyroscope step. Reused from step to step: copy what you keep. */
public class ReplayStep internal constructor() {
    /** Timestamp of the gyroscope sample, ns. */
    public var timestampNs: Long = 0L
        internal set

    /** Seconds since the recording's origin. */
    public var timeS: Double = 0.0
        internal set

    /** True once the filter has an orientation; before that [orientation] is NaN. */
    public var initialised: Boolean = false
        internal set

    /** Orientation [w, x, y, z], sensor → ENU. */
    public val orientation: DoubleArray = DoubleArray(4)

    /** The latest accelerometer reading (specific force, m/s², device frame); NaN before the first. */
    public val specificForce: DoubleArray = doubleArrayOf(Double.NaN, Double.NaN, Double.NaN)

    /** This step's gyroscope reading (rad/s, device frame). */
    public val angularVelocity: DoubleArray = DoubleArray(3)

    /** The latest magnetometer reading (µT, device frame); NaN before the first and without one. */
    public val magneticField: DoubleArray = doubleArrayOf(Double.NaN, Double.NaN, Double.NaN)

    /** Timestamps of the held accelerometer and magnetometer readings, ns (Long.MIN_VALUE before the first): the offline pass's freshness. */
    internal var accelerometerNs: Long = Long.MIN_VALUE
    internal var magnetometerNs: Long = Long.MIN_VALUE
}

/** Receives replay results. */
public interface ReplayListener {
    /** After each gyroscope sample. */
    public fun step(step: ReplayStep)

    /** For each event of a reference stream (rotation vectors, truth, the live orientation), before the gyroscope step of the same instant. */
    public fun reference(stream: SessionStream, timestampNs: Long, values: DoubleArray) {}
}

/** Counts of what a replay read. */
public data class ReplayCounts(val events: Long, val gyroscope: Long, val accelerometer: Long, val magnetometer: Long, val firstTimestampNs: Long, val lastTimestampNs: Long)

/**
 * Runs a [MadgwickFilter] with [settings] (output frame forced to ENU) over events. Reusable for
 * one run only.
 */
public class Replayer(settings: FilterSettings = FilterSettings()) {
    /** The filter being run (for diagnostics after the run). */
    public val filter: MadgwickFilter = MadgwickFilter(settings.copy(outputFrame = WorldFrame.ENU))

    /**
     * After a run, how far the magnetometer's heading strayed from the gyroscope's for longer than a few seconds:
     * the median, over the recording, of the field's heading (low-passed over 5 s) against a line fitted over the
     * last minute in the frame the gyroscope alone carries, degrees; NaN without a magnetometer, in IMU mode, or
     * before 20 s of steps with the field. Rooms and rigs score low, walks through buildings, whose field errors persist
     * over tens of metres, mostly higher (the figures: docs/ACCURACY.md, "Does the recording look like a building?").
     */
    public val fieldPersistenceDeg: Double get() = persistence?.median() ?: Double.NaN

    /**
     * After [runOffline]: whether its passes learnt no gyroscope bias in motion, the field's persistence being above
     * OfflineSettings.buildingPersistence (docs/ACCURACY.md, "Does the recording look like a building?").
     */
    public var offlineWithoutMotionBias: Boolean = false
        private set

    private val persistence = if (filter.settings.mode == FilterMode.MARG) FieldPersistence() else null
    private val maxGapNs = (filter.settings.maxGap * 1e9).toLong()
    private val seen = DoubleArray(3)
    private var persistenceSteps = 0L
    private var persistenceStarted = false
    private var persistenceFieldNs = Long.MIN_VALUE

    /**
     * Replays [events] to [listener]; t = 0 s is [originNs], or the first event when null.
     * [progress], if given, is called with the number of events read, about every 65,536 events.
     */
    @JvmOverloads
    public fun run(events: SensorEvents, originNs: Long?, listener: ReplayListener, progress: ((Long) -> Unit)? = null, source: String = "input"): ReplayCounts =
        usable(source, runCausal(events, originNs, listener, progress))

    /**
     * The offline estimate of [events] (docs/ACCURACY.md, "Offline"): the same steps, outputs and
     * counts as [run], but each step's orientation uses the whole recording, the samples after it as
     * well as those before (a pass forward, one backward over the same samples, and their
     * combination; [offline] has the settings beyond the filter's). [listener] gets every step and
     * reference event in time order after the whole input has been read. Memory does not grow
     * with the length: what the backward pass needs goes to a temporary file in [tempDir] (the
     * system's when null), which is removed however the run ends.
     */
    @JvmOverloads
    public fun runOffline(
        events: SensorEvents, originNs: Long?, listener: ReplayListener, progress: ((Long) -> Unit)? = null, source: String = "input",
        offline: OfflineSettings = OfflineSettings(), tempDir: java.nio.file.Path? = null,
    ): ReplayCounts = OfflineReplay(filter, offline, tempDir).use { pass ->
        offlineWithoutMotionBias = false
        val counts = usable(source, runCausal(events, originNs, pass, progress))
        offlineWithoutMotionBias = pass.finish(listener, fieldPersistenceDeg)
        counts
    }

    private fun runCausal(events: SensorEvents, originNs: Long?, listener: ReplayListener, progress: ((Long) -> Unit)?): ReplayCounts =
        if (events is RowEvents) runRows(events, originNs, listener, progress) else runEvents(events, originNs, listener, progress)

    /**
     * [counts] when most of the input was usable; a gyroscope stepping back by more than
     * SensorRanges.MAX_STEP_BACK_S, or fewer than half the samples usable, is an error naming [source].
     */
    private fun usable(source: String, counts: ReplayCounts): ReplayCounts {
        val d = filter.diagnostics()
        fun fail(reason: String): Nothing = throw DataFormatException(source, 0, 0, reason)
        if (largestStepBackNs > SensorRanges.MAX_STEP_BACK_S * 1e9) {
            fun s(ns: Long) = "%.3f".format(java.util.Locale.ROOT, secondsBetween(counts.firstTimestampNs, ns))
            fail("gyroscope timestamps step back by ${"%.3f".format(java.util.Locale.ROOT, largestStepBackNs * 1e-9)} s at gyroscope sample $stepBackSample " +
                "(from t = ${s(stepBackFromNs)} s to ${s(stepBackFromNs - largestStepBackNs)} s, times from the first sample; in a plain table, its data row $stepBackSample): " +
                "the recording is out of order (pieces joined?); sort it by time")
        }
        if (counts.gyroscope > 0 && d.skippedTimestamp * 2 > counts.gyroscope) {
            fail("${d.skippedTimestamp} of ${counts.gyroscope} gyroscope timestamps do not advance: fewer than half the samples are usable; sort the rows by time")
        }
        val skipped = d.skippedOutOfRange + d.skippedNonFinite
        val perStream = maxOf(counts.gyroscope, counts.accelerometer, counts.magnetometer)
        if (perStream > 0 && skipped * 2 > perStream) {
            fail("$skipped readings are beyond any phone's range (${d.skippedOutOfRange}) or not finite (${d.skippedNonFinite}), over half of a stream's $perStream samples: " +
                "fewer than half the samples are usable; check the columns and their units")
        }
        return counts
    }

    /** The largest step back of the gyroscope's timestamps, ns, and where it was. */
    private var largestStepBackNs = 0L
    private var stepBackFromNs = 0L
    // Gyroscope samples seen, and the 1-based number of the one that stepped back furthest.
    private var gyroscopeSamples = 0L
    private var stepBackSample = 0L
    private var lastGyroNs = Long.MIN_VALUE

    /**
     * True when a reading is one the filter takes (finite, within [limit] per axis): only such a
     * reading is held in the step, so the rows and the linear acceleration never carry one the
     * filter skipped (a reading of 1e308 m/s²).
     */
    private fun reading(x: Double, y: Double, z: Double, limit: Double): Boolean =
        x.isFinite() && y.isFinite() && z.isFinite() && abs(x) <= limit && abs(y) <= limit && abs(z) <= limit

    private fun gyroscopeTime(t: Long) {
        gyroscopeSamples++
        if (lastGyroNs != Long.MIN_VALUE && t < lastGyroNs) {
            val back = secondsBetween(t, lastGyroNs) * 1e9
            if (back > largestStepBackNs) { largestStepBackNs = back.toLong(); stepBackFromNs = lastGyroNs; stepBackSample = gyroscopeSamples }
        }
        lastGyroNs = t
    }

    private fun runEvents(events: SensorEvents, originNs: Long?, listener: ReplayListener, progress: ((Long) -> Unit)?): ReplayCounts {
        val step = ReplayStep()
        var origin = originNs
        var n = 0L
        var gyro = 0L
        var acc = 0L
        var mag = 0L
        var first = 0L
        var last = 0L
        val f = filter
        while (events.next()) {
            val t = events.timestampNs
            val v = events.values
            if (origin == null) origin = t
            if (n == 0L) first = t
            last = t
            n++
            if (progress != null && (n and 0xFFFF) == 0L) progress(n)
            val stream = events.stream
            if (f.update(stream, t, v[0], v[1], v[2])) {
                gyro++
                gyroscopeStep(step, t, v[0], v[1], v[2], origin, listener)
            } else when (stream) {
                SessionStream.ACCELEROMETER -> { acc++; accelerometerHeld(step, t, v[0], v[1], v[2]) }
                SessionStream.MAGNETOMETER -> { mag++; magnetometerHeld(step, t, v[0], v[1], v[2]) }
                SessionStream.ROTATION_VECTOR, SessionStream.GAME_ROTATION_VECTOR, SessionStream.TRUTH, SessionStream.ORIENTATION ->
                    listener.reference(stream, t, v)
                else -> Unit // uncalibrated streams and diagnostics are not filter inputs
            }
        }
        return ReplayCounts(n, gyro, acc, mag, first, last)
    }

    /**
     * [run] on rows: per row the filter calls the events accelerometer, magnetometer, gyroscope
     * would make, in that order, so every step and count is the same.
     */
    private fun runRows(events: RowEvents, originNs: Long?, listener: ReplayListener, progress: ((Long) -> Unit)?): ReplayCounts {
        val step = ReplayStep()
        val f = filter
        val r = events.row
        val mag = events.hasMagnetometer
        var origin = originNs
        var rows = 0L
        var magnetometer = 0L
        var first = 0L
        var last = 0L
        while (events.nextRow()) {
            val t = events.timestampNs
            if (origin == null) origin = t
            if (rows == 0L) first = t
            last = t
            rows++
            if (progress != null && (rows and 0x3FFF) == 0L) progress(rows * 2 + magnetometer)
            f.updateAccelerometer(t, r[3], r[4], r[5])
            accelerometerHeld(step, t, r[3], r[4], r[5])
            if (mag && ImuTableReader.hasMagnetometerReading(r)) {
                magnetometer++
                f.updateMagnetometer(t, r[6], r[7], r[8])
                magnetometerHeld(step, t, r[6], r[7], r[8])
            }
            f.updateGyroscope(t, r[0], r[1], r[2])
            gyroscopeStep(step, t, r[0], r[1], r[2], origin, listener)
        }
        return ReplayCounts(rows * 2 + magnetometer, rows, rows, magnetometer, first, last)
    }

    /** The accelerometer reading the filter was just given, held in [step] if the filter takes it ([reading]). */
    private fun accelerometerHeld(step: ReplayStep, t: Long, x: Double, y: Double, z: Double) {
        if (!reading(x, y, z, SensorRanges.ACCELEROMETER_M_S2)) return
        step.specificForce[0] = x; step.specificForce[1] = y; step.specificForce[2] = z
        step.accelerometerNs = t
    }

    /** The magnetometer reading the filter was just given, held in [step] if the filter takes it ([reading]). */
    private fun magnetometerHeld(step: ReplayStep, t: Long, x: Double, y: Double, z: Double) {
        if (!reading(x, y, z, SensorRanges.MAGNETOMETER_UT)) return
        step.magneticField[0] = x; step.magneticField[1] = y; step.magneticField[2] = z
        step.magnetometerNs = t
    }

    /** After the filter's gyroscope step on (x, y, z) at [t]: the step, with the filter's orientation, to [listener]. */
    private fun gyroscopeStep(step: ReplayStep, t: Long, x: Double, y: Double, z: Double, origin: Long, listener: ReplayListener) {
        gyroscopeTime(t)
        step.angularVelocity[0] = x; step.angularVelocity[1] = y; step.angularVelocity[2] = z
        step.timestampNs = t
        step.timeS = secondsBetween(origin, t)
        step.initialised = filter.isInitialised
        if (step.initialised) {
            filter.orientationInto(step.orientation)
        } else {
            step.orientation.fill(Double.NaN)
        }
        persistence?.let { judge(it, step, t, x, y, z) }
        listener.step(step)
    }

    /**
     * The step at [t] (raw rate x, y, z) to the recording's [FieldPersistence] as the filter took it: a step it
     * integrated (over its own step length; after a gap, unlinked), its start, or nothing where it skipped the
     * sample (a timestamp that stalls or steps back, a reading not finite); with the held field if it is new.
     */
    private fun judge(p: FieldPersistence, step: ReplayStep, t: Long, x: Double, y: Double, z: Double) {
        val f = filter
        val steps = f.stepsTaken
        val stepped = steps != persistenceSteps
        val started = !persistenceStarted && f.isInitialised
        if (!stepped && !started) return
        persistenceSteps = steps
        persistenceStarted = f.isInitialised
        val linked = stepped && !f.lastStepAfterGap
        val fieldNs = step.magnetometerNs
        val newField = fieldNs != Long.MIN_VALUE && fieldNs != persistenceFieldNs && t - fieldNs <= maxGapNs
        if (newField) {
            persistenceFieldNs = fieldNs
            f.fieldSeenInto(step.magneticField, seen)
        }
        p.step(step.orientation, linked, x, y, z, if (linked) f.lastStepDt else 0.0, newField, seen)
    }

    public companion object {
        /**
         * (toNs − fromNs) in seconds, for any two timestamps: where the difference does not fit
         * in a Long (timestamps of opposite sign far apart) it is taken in Double instead of
         * wrapping round.
         */
        @JvmStatic
        public fun secondsBetween(fromNs: Long, toNs: Long): Double {
            val d = toNs - fromNs
            val overflow = ((toNs xor fromNs) and (toNs xor d)) < 0
            return if (overflow) (toNs.toDouble() - fromNs.toDouble()) * 1e-9 else d * 1e-9
        }
    }
}

/** The offline estimate (filter/offline) as a [ReplayListener] for the first pass; [finish] hands every step and reference on. */
private class OfflineReplay(filter: MadgwickFilter, offline: OfflineSettings, tempDir: java.nio.file.Path?) : ReplayListener, java.io.Closeable {
    private val passes = OfflinePasses(filter, offline, tempDir)

    override fun step(step: ReplayStep) = passes.step(
        step.timestampNs, step.timeS, step.accelerometerNs, step.magnetometerNs,
        step.angularVelocity, step.specificForce, step.magneticField, step.orientation,
    )

    override fun reference(stream: SessionStream, timestampNs: Long, values: DoubleArray) = passes.reference(stream, timestampNs, values)

    /** Returns whether the passes ran without the bias estimate in motion (OfflinePasses.finish). */
    fun finish(listener: ReplayListener, persistenceDeg: Double): Boolean {
        val step = ReplayStep()
        return passes.finish(step.angularVelocity, step.specificForce, step.magneticField, step.orientation, object : OfflineOutput {
            override fun row(timestampNs: Long, timeS: Double) {
                step.timestampNs = timestampNs
                step.timeS = timeS
                step.initialised = !step.orientation[0].isNaN()
                listener.step(step)
            }

            override fun reference(stream: SessionStream, timestampNs: Long, values: DoubleArray) = listener.reference(stream, timestampNs, values)
        }, persistenceDeg)
    }

    override fun close() = passes.close()
}
