package dev.motionfusion.app.fusion

import dev.motionfusion.app.sensor.RateMeter
import dev.motionfusion.app.sensor.SensorKind
import dev.motionfusion.app.sensor.SensorSample
import dev.motionfusion.app.sensor.SensorStreams
import dev.motionfusion.core.Orientations
import dev.motionfusion.core.Quaternion
import dev.motionfusion.core.RotationArrays
import dev.motionfusion.core.filter.FilterMode
import dev.motionfusion.core.filter.FilterSettings
import dev.motionfusion.core.filter.MadgwickFilter
import dev.motionfusion.core.sensormanager.SensorManagerMath
import java.util.EnumMap
import kotlin.math.sqrt
import dev.motionfusion.app.settings.LiveSettings

/**
 * The fusion of one stream of samples, free of Android threading (tested on the JVM).
 *
 * Every sample is folded in, none skipped: per-sensor rate and jitter are measured, and the
 * orientation is computed in the [EffectiveMode] for the sensors in [available]:
 * - MARG/IMU: fusion-core's Madgwick filter with its pairing rule: accelerometer and
 *   magnetometer samples are held, each gyroscope sample steps the filter with them;
 * - ACC_MAG: getRotationMatrix on the latest accelerometer and magnetometer readings;
 * - TILT_ONLY: the smallest rotation taking the measured up to the world's up.
 * Rotation vector samples are kept as references. [onSample] allocates nothing; [snapshot]
 * allocates the published state. Not thread-safe: one thread calls everything.
 */
class FusionPipeline(
    private val available: Set<SensorKind>,
    settings: LiveSettings,
    /**
     * The gyroscope's saturation threshold from its range (sensor/GyroSaturation), rad/s, used
     * while the setting is at its default; null keeps the setting.
     */
    private val gyroSaturationRadS: Double? = null,
) {
    var settings: LiveSettings = settings
        private set
    var mode: EffectiveMode = effectiveMode(available, settings.mode)
        private set

    /** The filter in use; rebuilt by [reconfigure] when its settings change. */
    var filter: MadgwickFilter = newFilter()
        private set

    private val kinds = SensorKind.entries
    private val meters = Array(kinds.size) { RateMeter() }
    private val accuracy = IntArray(kinds.size) { Int.MIN_VALUE }
    private val values = Array(kinds.size) { FloatArray(4) }
    private val seen = BooleanArray(kinds.size)

    private val q = DoubleArray(4)
    private var hasOrientation = false
    private val rv = DoubleArray(4)
    private val grv = DoubleArray(4)
    private var rvHeadingAccuracy = Float.NaN
    private val r = FloatArray(9)
    private val acc = FloatArray(3)
    private val mag = FloatArray(3)
    private var lastT = 0L

    // 6D: rotation about up applied to the filter's output so that the relative heading starts at 0.
    private var hasYawOffset = false
    private var yawOffset = 0.0

    /**
     * Applies new settings. The filter is rebuilt (and restarts from the next samples) only when
     * its own settings or the effective mode change; the convention and rate don't touch it.
     */
    fun reconfigure(newSettings: LiveSettings) {
        val newMode = effectiveMode(available, newSettings.mode)
        val filterChanged = newSettings.filter != settings.filter || newMode != mode
        settings = newSettings
        mode = newMode
        if (filterChanged) restartFilter()
    }

    private val scratch = FloatArray(5)

    /** Folds one sample in (the value form; the capture calls [onEvent]). */
    fun onSample(s: SensorSample) {
        scratch[0] = s.x; scratch[1] = s.y; scratch[2] = s.z; scratch[3] = s.w; scratch[4] = s.headingAccuracyRad
        onEvent(s.kind, s.timestampNs, s.accuracy, scratch, 0, if (s.kind.isRotationVector) 5 else 3)
    }

    /**
     * Folds one event in: [count] values of [kind] at [v]`[o..]` (x, y, z; for the rotation
     * vectors also w and the heading accuracy). Allocation-free. Returns true when the event
     * stepped the Madgwick [filter] (a gyroscope event with the filter initialised).
     */
    fun onEvent(kind: SensorKind, timestampNs: Long, accuracy: Int, v: FloatArray, o: Int, count: Int): Boolean =
        fold(kind, timestampNs, accuracy, v, o, count, v[o].toDouble(), v[o + 1].toDouble(), v[o + 2].toDouble())

    private val correctedScratch = FloatArray(3)

    /**
     * Folds in one calibrated reading of a three-axis [kind] (accelerometer, gyroscope,
     * magnetometer): the filter gets [x], [y], [z] as they are, as `fusion replay --calibration`
     * feeds them; the screen shows them rounded to floats. Allocation-free; returns as [onEvent].
     */
    fun onCorrected(kind: SensorKind, timestampNs: Long, accuracy: Int, x: Double, y: Double, z: Double): Boolean {
        val f = correctedScratch
        f[0] = x.toFloat(); f[1] = y.toFloat(); f[2] = z.toFloat()
        return fold(kind, timestampNs, accuracy, f, 0, 3, x, y, z)
    }

    private fun fold(kind: SensorKind, timestampNs: Long, accuracy: Int, v: FloatArray, o: Int, count: Int, x: Double, y: Double, z: Double): Boolean {
        val i = kind.ordinal
        meters[i].add(timestampNs)
        this.accuracy[i] = accuracy
        val kept = values[i]
        kept[0] = v[o]; kept[1] = v[o + 1]; kept[2] = v[o + 2]
        kept[3] = if (count >= 4) v[o + 3] else Float.NaN
        seen[i] = true
        lastT = timestampNs
        var stepped = false
        when (mode.mode) {
            FusionMode.MARG, FusionMode.IMU -> stepped = filterSample(kind, timestampNs, x, y, z)
            FusionMode.ACC_MAG -> if (kind == SensorKind.ACCELEROMETER || kind == SensorKind.MAGNETOMETER) accMag()
            FusionMode.TILT_ONLY -> if (kind == SensorKind.ACCELEROMETER) tilt(x, y, z)
            FusionMode.NONE -> Unit
        }
        when (kind) {
            SensorKind.ROTATION_VECTOR -> {
                unitQuaternion(v, o, count, rv)
                rvHeadingAccuracy = if (count >= 5) v[o + 4] else Float.NaN
            }
            SensorKind.GAME_ROTATION_VECTOR -> unitQuaternion(v, o, count, grv)
            else -> Unit
        }
        return stepped
    }

    /**
     * Starts the filter afresh from the next events (the settings unchanged): a recording starts
     * with a filter in the state `fusion replay` starts in, so that replaying it gives what was live.
     */
    fun restartFilter() {
        filter = newFilter()
        hasYawOffset = false
        if (mode.mode == FusionMode.MARG || mode.mode == FusionMode.IMU) hasOrientation = false
    }

    /** The settings of the filter in use (the mode falls back to 6D without magnetometer). */
    val filterSettings get() = filter.settings

    /** The current orientation (device → ENU) into out[0..3]; false (out untouched) when there is none yet. */
    fun orientationInto(out: DoubleArray): Boolean {
        if (!hasOrientation) return false
        q.copyInto(out)
        return true
    }

    /** Achieved rate of [kind], Hz (NaN before two samples). */
    fun rateHz(kind: SensorKind): Double = meters[kind.ordinal].rateHz()

    /** An immutable copy of everything the UI shows. */
    fun snapshot(): FusionState {
        val stats = EnumMap<SensorKind, SensorStats>(SensorKind::class.java)
        for (k in kinds) {
            val i = k.ordinal
            if (!seen[i]) continue
            val m = meters[i]
            val v = values[i]
            stats[k] = SensorStats(m.samples, m.rateHz(), m.jitterMs(), m.duplicates, m.backwards, accuracy[i], v[0], v[1], v[2], v[3])
        }
        val usesFilter = mode.mode == FusionMode.MARG || mode.mode == FusionMode.IMU
        val d = if (usesFilter) filter.diagnostics() else null
        val magV = values[SensorKind.MAGNETOMETER.ordinal]
        return FusionState(
            mode = mode,
            settings = settings,
            orientation = if (hasOrientation) Quaternion(q[0], q[1], q[2], q[3]) else null,
            rotationVector = if (seen[SensorKind.ROTATION_VECTOR.ordinal]) Quaternion(rv[0], rv[1], rv[2], rv[3]) else null,
            rotationVectorHeadingAccuracyRad = rvHeadingAccuracy.takeIf { it.isFinite() && it >= 0f }?.toDouble(),
            gameRotationVector = if (seen[SensorKind.GAME_ROTATION_VECTOR.ordinal]) Quaternion(grv[0], grv[1], grv[2], grv[3]) else null,
            sensors = stats,
            magneticFieldUt = if (seen[SensorKind.MAGNETOMETER.ordinal]) {
                sqrt((magV[0] * magV[0] + magV[1] * magV[1] + magV[2] * magV[2]).toDouble())
            } else {
                null
            },
            atRest = d?.atRest ?: false,
            magneticDisturbance = d?.magneticDisturbance ?: false,
            accelerometerRejected = d?.accelerometerRejected ?: false,
            gyroBiasRadS = d?.gyroBias?.let { doubleArrayOf(it.x, it.y, it.z) },
            filterSteps = d?.gyroscopeSteps ?: 0L,
            timestampNs = lastT,
        )
    }

    private fun newFilter(): MadgwickFilter {
        // The gyroscope's range stands in for the setting while it is at its default; a value the user chose (or off) stays.
        val fs = settings.filter.let {
            if (gyroSaturationRadS != null && it.gyroSaturation == DEFAULT_GYRO_SATURATION) it.copy(gyroSaturation = gyroSaturationRadS) else it
        }
        // 9D requested without a magnetometer: the filter runs 6D.
        return MadgwickFilter(if (mode.mode == FusionMode.IMU) fs.copy(mode = FilterMode.IMU) else fs)
    }

    /** [kind]'s reading to the filter; true when it stepped the filter (a gyroscope reading) and there is an orientation. */
    private fun filterSample(kind: SensorKind, t: Long, x: Double, y: Double, z: Double): Boolean {
        val stream = SensorStreams.ofAndroidType(kind.androidType) ?: return false
        if (!filter.update(stream, t, x, y, z) || !filter.isInitialised) return false
        filter.orientationInto(q)
        if (mode.mode == FusionMode.IMU) relativeHeading()
        hasOrientation = true
        return true
    }

    /**
     * 6D has no north: the filter starts with the device's x axis towards its x ("north"), so the
     * first heading would be an arbitrary number. Turn the output about up by the first azimuth
     * ψ (fusion-core's [Orientations.azimuth]; q ← [Orientations.removeHeading] by −ψ, the azimuth
     * counting towards east, i.e. about −z) so that the relative heading starts at 0; tilt is unchanged.
     */
    private fun relativeHeading() {
        if (!hasYawOffset) {
            yawOffset = Orientations.azimuth(q)
            hasYawOffset = true
        }
        Orientations.removeHeading(q, -yawOffset)
    }

    private fun accMag() {
        val a = values[SensorKind.ACCELEROMETER.ordinal]
        val m = values[SensorKind.MAGNETOMETER.ordinal]
        if (!seen[SensorKind.ACCELEROMETER.ordinal] || !seen[SensorKind.MAGNETOMETER.ordinal]) return
        acc[0] = a[0]; acc[1] = a[1]; acc[2] = a[2]
        mag[0] = m[0]; mag[1] = m[1]; mag[2] = m[2]
        // Free fall or field along gravity: keep the previous orientation.
        if (!SensorManagerMath.getRotationMatrix(r, null, acc, mag)) return
        RotationArrays.rotationMatrixToQuaternion(r, q)
        hasOrientation = true
    }

    /** Tilt only: the shortest rotation taking the measured up u (device frame) onto the world's up, q = [1 + u·z, u × z] normalised (device → world). */
    private fun tilt(ax: Double, ay: Double, az: Double) {
        val n = sqrt(ax * ax + ay * ay + az * az)
        if (!(n > FREE_FALL_MS2)) return
        val ux = ax / n
        val uy = ay / n
        val uz = az / n
        val w = 1.0 + uz
        if (w < 1e-9) {
            // Upside down: 180° about the device's y axis.
            q[0] = 0.0; q[1] = 0.0; q[2] = 1.0; q[3] = 0.0
        } else {
            // The rotation taking u to z (device → world), axis u × z = (uy, −ux, 0).
            val k = 1.0 / sqrt(w * w + uy * uy + ux * ux)
            q[0] = w * k; q[1] = uy * k; q[2] = -ux * k; q[3] = 0.0
        }
        hasOrientation = true
    }

    private fun unitQuaternion(v: FloatArray, o: Int, count: Int, out: DoubleArray) {
        val x = v[o].toDouble()
        val y = v[o + 1].toDouble()
        val z = v[o + 2].toDouble()
        val w = if (count < 4 || v[o + 3].isNaN()) sqrt((1.0 - x * x - y * y - z * z).coerceAtLeast(0.0)) else v[o + 3].toDouble()
        val n = sqrt(w * w + x * x + y * y + z * z)
        if (!(n > 0.0) || !n.isFinite()) return
        out[0] = w / n; out[1] = x / n; out[2] = y / n; out[3] = z / n
    }

    private companion object {
        /** Below this the accelerometer measures no usable gravity (10 % of g, as getRotationMatrix). */
        const val FREE_FALL_MS2 = 0.981

        val DEFAULT_GYRO_SATURATION = FilterSettings().gyroSaturation
    }
}
