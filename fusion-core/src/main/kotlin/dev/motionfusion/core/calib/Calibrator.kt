/*
 * One pass over a recording that fits everything it supports: the magnetometer (preferring the
 * uncalibrated stream), the gyroscope bias (preferring the uncalibrated stream) and the
 * accelerometer. The same code serves `fusion calibrate` and the app.
 */
package dev.motionfusion.core.calib

import dev.motionfusion.core.event.SensorEvents
import dev.motionfusion.core.event.SessionStream

public object Calibrator {
    /** The magnetometer stream a calibration is fitted on, given the recording's [streams]. */
    @JvmStatic
    public fun magnetometerStream(streams: Set<SessionStream>): SessionStream? = when {
        SessionStream.MAGNETOMETER_UNCALIBRATED in streams -> SessionStream.MAGNETOMETER_UNCALIBRATED
        SessionStream.MAGNETOMETER in streams -> SessionStream.MAGNETOMETER
        else -> null
    }

    /** The gyroscope stream a bias is fitted on. */
    @JvmStatic
    public fun gyroscopeStream(streams: Set<SessionStream>): SessionStream? = when {
        SessionStream.GYROSCOPE_UNCALIBRATED in streams -> SessionStream.GYROSCOPE_UNCALIBRATED
        SessionStream.GYROSCOPE in streams -> SessionStream.GYROSCOPE
        else -> null
    }

    /**
     * Reads [events] (a recording with [streams]) once and fits each sensor it holds. [progress],
     * if given, is called with the number of events read every 65,536 events.
     */
    @JvmStatic
    @JvmOverloads
    public fun calibrate(
        events: SensorEvents,
        streams: Set<SessionStream>,
        settings: CalibrationSettings = CalibrationSettings(),
        source: String = "",
        recording: String = "",
        progress: ((Long) -> Unit)? = null,
    ): Calibration {
        val magStream = magnetometerStream(streams)
        val gyroStream = gyroscopeStream(streams)
        val hasAcc = SessionStream.ACCELEROMETER in streams
        val mag = magStream?.let { MagnetometerFitter(settings, it) }
        val still = gyroStream?.let { StillPeriods(settings, it) }
        events.forEachEvent(progress) { stream, t, v ->
            when (stream) {
                magStream -> mag?.add(v[0], v[1], v[2])
                gyroStream -> still?.gyroscope(t, v[0], v[1], v[2])
                SessionStream.ACCELEROMETER -> still?.accelerometer(v[0], v[1], v[2])
                else -> Unit
            }
        }
        val refused = LinkedHashMap<String, String>()
        fun <T> take(name: String, fit: Fit<T>?, missing: String): T? = when (fit) {
            is Fit.Done -> fit.value
            is Fit.Refused -> { refused[name] = fit.reason; null }
            null -> { refused[name] = missing; null }
        }
        val m = take("magnetometer", mag?.fit(), "no magnetometer stream")
        val g = take("gyroscope", still?.gyroscopeFit(), "no gyroscope stream")
        val a = take("accelerometer", if (hasAcc) still?.accelerometerFit() else null,
            if (hasAcc) "no gyroscope stream to tell still periods" else "no accelerometer stream")
        return Calibration(m, g, a, refused, source, recording)
    }
}

/** Reads every event, calling [progress] with the count every 65,536 events. */
internal inline fun SensorEvents.forEachEvent(noinline progress: ((Long) -> Unit)?, action: (SessionStream, Long, DoubleArray) -> Unit) {
    var n = 0L
    while (next()) {
        n++
        if (progress != null && (n and 0xFFFF) == 0L) progress(n)
        action(stream, timestampNs, values)
    }
}

/**
 * Where each reading goes once [calibration] is applied, for replay ([CalibratedEvents]) and the
 * app's live filter alike: corrected readings feed the filter as the calibrated streams it reads
 * (ACCELEROMETER, GYROSCOPE, MAGNETOMETER). When a calibration was fitted on an uncalibrated
 * stream, that stream is corrected and becomes the calibrated one, and the recording's own
 * calibrated stream is left out (Android's correction would otherwise be applied twice).
 * Other streams pass unchanged. Allocation-free.
 */
public class CalibrationRoute(calibration: Calibration) {
    private val targets = arrayOfNulls<SessionStream>(SessionStream.entries.size)
    private val corrections = arrayOfNulls<SensorCorrection>(SessionStream.entries.size)

    init {
        for (s in SessionStream.entries) targets[s.ordinal] = s
        fun route(from: SessionStream?, to: SessionStream, c: SensorCorrection?) {
            if (from == null || c == null) return
            if (from != to) targets[to.ordinal] = null
            targets[from.ordinal] = to
            corrections[from.ordinal] = c
        }
        route(calibration.accelerometer?.stream, SessionStream.ACCELEROMETER, calibration.accelerometer?.correction)
        route(calibration.gyroscope?.stream, SessionStream.GYROSCOPE, calibration.gyroscope?.correction)
        route(calibration.magnetometer?.stream, SessionStream.MAGNETOMETER, calibration.magnetometer?.correction)
    }

    /** The stream readings of [s] become, or null when they are left out. */
    public fun target(s: SessionStream): SessionStream? = targets[s.ordinal]

    /** The correction of readings of [s], or null (passed unchanged). */
    public fun correction(s: SessionStream): SensorCorrection? = corrections[s.ordinal]
}

/**
 * [inner] with a [calibration] applied ([CalibrationRoute]). Allocates nothing per event. Throws
 * IllegalArgumentException when the recording ([streams]) lacks a stream the calibration applies to.
 */
public class CalibratedEvents(private val inner: SensorEvents, calibration: Calibration, streams: Set<SessionStream>) : SensorEvents {
    init {
        val missing = calibration.streams().filter { it !in streams }
        require(missing.isEmpty()) {
            "the calibration applies to ${missing.joinToString(", ") { it.key }}, which the recording does not have"
        }
    }

    private val route = CalibrationRoute(calibration)
    override val values: DoubleArray = DoubleArray(8)
    override var stream: SessionStream = SessionStream.ACCELEROMETER
        private set

    override val timestampNs: Long get() = inner.timestampNs
    override val accuracy: Int get() = inner.accuracy

    override fun next(): Boolean {
        while (inner.next()) {
            val s = inner.stream
            val out = route.target(s) ?: continue
            inner.values.copyInto(values, 0, 0, minOf(inner.values.size, values.size))
            route.correction(s)?.applyInPlace(values)
            stream = out
            return true
        }
        return false
    }

    override fun close(): Unit = inner.close()
}
