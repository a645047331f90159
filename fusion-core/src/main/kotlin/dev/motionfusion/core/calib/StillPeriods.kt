/*
 * Still periods of a recording: windows of CalibrationSettings.stillWindowS on the gyroscope's
 * timestamps in which the gyroscope and the accelerometer hardly vary. They give the gyroscope
 * bias (its mean while still) and the accelerometer poses (its mean in each still pose).
 * Device frame; rad/s, m/s²; timestamps ns.
 */
package dev.motionfusion.core.calib

import dev.motionfusion.core.Vector3
import dev.motionfusion.core.event.SessionStream
import kotlin.math.acos
import kotlin.math.sqrt

/** Per-axis sums of one window or pose. */
internal class AxisSums {
    var n = 0L
    val sum = DoubleArray(3)
    val sumSq = DoubleArray(3)

    fun add(x: Double, y: Double, z: Double) {
        n++
        sum[0] += x; sum[1] += y; sum[2] += z
        sumSq[0] += x * x; sumSq[1] += y * y; sumSq[2] += z * z
    }

    fun mean(k: Int) = sum[k] / n
    fun variance(k: Int) = if (n > 1) maxOf(0.0, (sumSq[k] - sum[k] * sum[k] / n) / (n - 1)) else 0.0
    fun maxStd() = sqrt(maxOf(variance(0), variance(1), variance(2)))
    fun meanVector() = Vector3(mean(0), mean(1), mean(2))

    fun clear() {
        n = 0
        sum.fill(0.0); sumSq.fill(0.0)
    }
}

/**
 * Feed gyroscope ([gyroscope]) and accelerometer ([accelerometer]) samples in time order, then
 * read [gyroscopeFit], [poses] and [accelerometerFit] (reading ends the input: later samples are ignored).
 */
public class StillPeriods(
    private val settings: CalibrationSettings = CalibrationSettings(),
    private val gyroStream: SessionStream = SessionStream.GYROSCOPE,
    private val accStream: SessionStream = SessionStream.ACCELEROMETER,
) {
    private val windowNs = (settings.stillWindowS * 1e9).toLong()
    private val minPoseNs = (settings.minPoseS * 1e9 * 0.9).toLong()
    private var windowStart = Long.MIN_VALUE
    private var lastGyroNs = Long.MIN_VALUE
    private val gyro = AxisSums()
    private val acc = AxisSums()

    // Gyroscope bias: sample-weighted mean of still windows, and the spread of their means.
    private var stillWindows = 0
    private var stillSamples = 0L
    private var stillTimeNs = 0L
    private val biasSum = DoubleArray(3)
    private val windowMeanSum = DoubleArray(3)
    private val windowMeanSumSq = DoubleArray(3)
    private val noiseVarSum = DoubleArray(3)

    // Accelerometer poses: runs of still windows with the same mean.
    private val pose = AxisSums()
    private var poseNs = 0L
    private val poses = ArrayList<Pair<Vector3, Long>>()
    private var finished = false

    public fun gyroscope(timestampNs: Long, x: Double, y: Double, z: Double) {
        if (finished || !(x.isFinite() && y.isFinite() && z.isFinite())) return
        if (windowStart == Long.MIN_VALUE || timestampNs < lastGyroNs || timestampNs - lastGyroNs > windowNs / 2) {
            closeWindow(still = false)
            windowStart = timestampNs
        } else if (timestampNs - windowStart >= windowNs) {
            closeWindow(still = null)
            windowStart = timestampNs
        }
        lastGyroNs = timestampNs
        gyro.add(x, y, z)
    }

    public fun accelerometer(x: Double, y: Double, z: Double) {
        if (finished || windowStart == Long.MIN_VALUE || !(x.isFinite() && y.isFinite() && z.isFinite())) return
        acc.add(x, y, z)
    }

    /** Closes the current window; [still] null: judge it, false: it is broken (gap, step back). */
    private fun closeWindow(still: Boolean?) {
        val isStill = still != false && gyro.n >= 10 && gyro.maxStd() < settings.gyroStillStd && (acc.n == 0L || acc.maxStd() < settings.accStillStd)
        lastWindowStill = isStill
        if (isStill) {
            stillWindows++
            stillSamples += gyro.n
            stillTimeNs += lastGyroNs - windowStart
            for (k in 0 until 3) {
                biasSum[k] += gyro.sum[k]
                windowMeanSum[k] += gyro.mean(k)
                windowMeanSumSq[k] += gyro.mean(k) * gyro.mean(k)
                noiseVarSum[k] += gyro.variance(k)
            }
            if (acc.n > 0) {
                val m = acc.meanVector()
                if (pose.n > 0 && (m - pose.meanVector()).norm() > POSE_TOLERANCE) closePose()
                for (k in 0 until 3) { pose.sum[k] += acc.sum[k]; pose.sumSq[k] += acc.sumSq[k] }
                pose.n += acc.n
                poseNs += lastGyroNs - windowStart
            }
        } else {
            closePose()
        }
        gyro.clear()
        acc.clear()
    }

    private fun closePose() {
        if (pose.n > 0 && poseNs >= minPoseNs) poses += pose.meanVector() to pose.n
        pose.clear()
        poseNs = 0L
    }

    private fun finish() {
        if (finished) return
        finished = true
        closeWindow(still = null)
        closePose()
    }

    /** The gyroscope bias; refused when the recording was still for less than [CalibrationSettings.minStillS]. */
    public fun gyroscopeFit(): Fit<GyroscopeCalibration> {
        finish()
        val still = stillTimeNs * 1e-9
        if (stillWindows == 0 || still < settings.minStillS) {
            return Fit.Refused(
                "still for %.1f s (at least %.0f s needed): lay the phone on a table, untouched".format(java.util.Locale.ROOT, still, settings.minStillS),
                RefusalKind.NOT_STILL, listOf(still, settings.minStillS),
            )
        }
        val bias = Vector3(biasSum[0] / stillSamples, biasSum[1] / stillSamples, biasSum[2] / stillSamples)
        val w = stillWindows.toDouble()
        fun stdError(k: Int): Double {
            if (stillWindows < 2) return Double.NaN
            val mean = windowMeanSum[k] / w
            return sqrt(maxOf(0.0, (windowMeanSumSq[k] - w * mean * mean) / (w - 1)) / w)
        }
        return Fit.Done(GyroscopeCalibration(
            bias, gyroStream, still, stillWindows,
            Vector3(stdError(0), stdError(1), stdError(2)),
            Vector3(sqrt(noiseVarSum[0] / w), sqrt(noiseVarSum[1] / w), sqrt(noiseVarSum[2] / w)),
        ))
    }

    /** Whether the last window judged (of [CalibrationSettings.stillWindowS]) was still; false before the first. */
    public var lastWindowStill: Boolean = false
        private set

    /** How long the current still pose has lasted, s (0 while moving). */
    public val currentPoseS: Double get() = poseNs * 1e-9

    /**
     * The distinct poses so far (mean specific force of each, merged as [accelerometerFit]
     * merges them), without ending the input: the poses closed so far and the current one once
     * it has lasted [CalibrationSettings.minPoseS]. For a live prompt.
     */
    public fun distinctPoses(): List<Vector3> {
        val all = if (!finished && pose.n > 0 && poseNs >= minPoseNs) poses + (pose.meanVector() to pose.n) else poses
        return merged(all)
    }

    /** The still poses found: mean specific force and sample count. */
    public fun poses(): List<Pair<Vector3, Long>> {
        finish()
        return poses.toList()
    }

    /**
     * Offset and scale per axis from six or more distinct poses (each axis up and down once);
     * with twelve or more distinct poses also the misalignment (a symmetric matrix).
     */
    public fun accelerometerFit(): Fit<AccelerometerCalibration> {
        finish()
        val points = merged(poses)
        val need = "lay the phone still for ${settings.minPoseS.toInt()}+ s on each of its six faces"
        if (points.size < 6) return Fit.Refused("${points.size} distinct still poses (at least 6 needed): $need", RefusalKind.FEW_POSES, listOf(points.size.toDouble(), settings.minPoseS))
        for ((k, axis) in listOf("x", "y", "z").withIndex()) {
            val up = points.any { it[k] > 0.5 * settings.gravity }
            val down = points.any { it[k] < -0.5 * settings.gravity }
            if (!up || !down) {
                return Fit.Refused(
                    "the $axis axis was never pointed ${if (!up) "up" else "down"}: $need",
                    if (!up) RefusalKind.AXIS_NEVER_UP else RefusalKind.AXIS_NEVER_DOWN, listOf(k.toDouble(), settings.minPoseS),
                )
            }
        }
        val xyz = DoubleArray(3 * points.size)
        points.forEachIndexed { i, p -> xyz[3 * i] = p.x; xyz[3 * i + 1] = p.y; xyz[3 * i + 2] = p.z }
        var used = if (points.size >= 12) EllipsoidModel.FULL else EllipsoidModel.AXIS_ALIGNED
        var e = EllipsoidFit.fit(xyz, points.size, used)
        if (e == null && used == EllipsoidModel.FULL) {
            used = EllipsoidModel.AXIS_ALIGNED
            e = EllipsoidFit.fit(xyz, points.size, used)
        }
        if (e == null) return Fit.Refused("the poses do not determine an ellipsoid", RefusalKind.POSES_NO_ELLIPSOID)
        val c = e.correction(settings.gravity)
        val residual = sqrt(points.sumOf { val d = c.apply(it).norm() - settings.gravity; d * d } / points.size)
        return Fit.Done(AccelerometerCalibration(c, accStream, used, settings.gravity, points.size, residual))
    }

    /** Poses of the same direction (the same face up twice) merged into one point, weighted by their samples. */
    private fun merged(found: List<Pair<Vector3, Long>>): List<Vector3> {
        val clusters = ArrayList<AxisSums>()
        val firsts = ArrayList<Vector3>()
        for ((m, n) in found) {
            val i = firsts.indexOfFirst { angle(it, m) < settings.poseSeparation }
            val c = if (i >= 0) clusters[i] else AxisSums().also { clusters += it; firsts += m }
            for (k in 0 until 3) c.sum[k] += m[k] * n
            c.n += n
        }
        return clusters.map { it.meanVector() }
    }

    private companion object {
        /** Still windows whose mean specific force differs by more than this belong to different poses, m/s². */
        const val POSE_TOLERANCE = 0.1
    }

    private fun angle(a: Vector3, b: Vector3): Double = acos(((a dot b) / (a.norm() * b.norm())).coerceIn(-1.0, 1.0))
}
