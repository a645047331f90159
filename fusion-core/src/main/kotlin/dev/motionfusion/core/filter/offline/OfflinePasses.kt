/*
 * The offline estimate (`fusion replay --offline`): the orientation at each instant from the whole
 * recording, the samples after it as well as those before. One filter, three passes over the same
 * samples, all with the same settings:
 *  1. forward, as the causal replay (its counts and diagnostics are the replay's), writing each
 *     step's samples and orientation to a temporary file;
 *  2. backward in time over that file (gyroscope negated, the same accelerometer and magnetometer
 *     readings), starting from the forward pass's final state turned round (MadgwickFilter.turnAround),
 *     each step's orientation written back into the file;
 *  3. forward again, starting from the backward pass's final state (so it has converged already at
 *     the first sample), each step's orientation combined with the backward one of the same instant,
 *     its heading turned towards the heading smoother's (HeadingSmoother: filtered in pass 2, smoothed
 *     here) and handed on.
 * Across a gap in the recording a pass goes on from the other pass's orientation at the gap's far side
 * (MadgwickFilter.takeOrientation), not from the one it carried over. The combination weighs heading and
 * inclination apart, the heading by how recently each pass met a disturbed field (FieldReference). Both
 * combined estimates have then seen the whole recording; their errors lag in opposite directions (one
 * integrates the past, the other the future), so the combination cancels much of them.
 * Frames and units as Replayer's; orientations sensor → ENU, [w, x, y, z].
 */
package dev.motionfusion.core.replay

import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.filter.FilterMode
import dev.motionfusion.core.filter.MadgwickFilter
import dev.motionfusion.core.filter.SensorRanges
import dev.motionfusion.core.io.AtomicFiles
import dev.motionfusion.core.io.TemporaryFiles
import java.io.Closeable
import java.io.IOException
import java.nio.Buffer
import java.nio.ByteBuffer
import java.nio.ByteOrder
import java.nio.channels.FileChannel
import java.nio.file.Files
import java.nio.file.Path
import java.nio.file.StandardOpenOption
import kotlin.math.PI
import kotlin.math.abs
import kotlin.math.asin
import kotlin.math.atan
import kotlin.math.atan2
import kotlin.math.cos
import kotlin.math.exp
import kotlin.math.sin
import kotlin.math.sqrt

/**
 * Settings of the offline estimate beyond the filter's own ([dev.motionfusion.core.filter.FilterSettings]
 * applies to every pass alike). All chosen by cross-validation (docs/ACCURACY.md, "Offline").
 *
 * @property backwardWeight the backward pass's weight in the combination's heading (the rotation between the
 *   two passes' estimates about the vertical), 0…1, where neither pass has met a disturbed field lately; where
 *   one has, the other gets more ([OfflinePass.headingWeight]).
 * @property inclinationBackwardWeight the backward pass's weight in the combination's inclination (the
 *   rotation about a horizontal axis), 0…1.
 * @property headingSmoothing how far the combination's heading is then turned towards the heading smoother's
 *   ([HeadingSmoother]), 0…1; 0 leaves the smoother out.
 * @property smootherRestNoise the smoother's magnetometer heading noise while the rest detector says the device
 *   is at rest, as a density, rad·√s (the variance of one reading is its square over the step length).
 * @property smootherMotionNoise the same in motion, rad·√s.
 * @property smootherHeadingNoise the random walk of the heading the gyroscope integrates, rad/√s.
 * @property smootherBiasNoise the random walk of the gyroscope's bias about the vertical, rad/s/√s.
 * @property smootherRestSpread the largest spread of the field's magnitude while the device moves (a robust
 *   standard deviation, 1.4826 × the median absolute deviation, relative to the median magnitude) at which the
 *   smoother gives rest its trust ([smootherRestNoise]); above it a rest's readings count as the motion's
 *   ([smootherMotionNoise]); [Double.POSITIVE_INFINITY] trusts every rest. A magnitude that changes as the
 *   device turns means a magnetometer that is not calibrated or carries a magnet along: its heading error then
 *   depends on the orientation, and a rest holds one orientation's error however long it lasts
 *   (docs/ACCURACY.md, "Trust at rest only in a steady field").
 */
public data class OfflineSettings @JvmOverloads constructor(
    val backwardWeight: Double = 0.0,
    val inclinationBackwardWeight: Double = 0.5,
    val headingSmoothing: Double = 0.8,
    val smootherRestNoise: Double = 1.0 * DEGREE,
    val smootherMotionNoise: Double = 30.0 * DEGREE,
    val smootherHeadingNoise: Double = 0.02 * DEGREE,
    val smootherBiasNoise: Double = 0.005 * DEGREE,
    val smootherRestSpread: Double = 0.04,
) {
    init {
        require(backwardWeight in 0.0..1.0) { "backwardWeight must be within 0…1, not $backwardWeight" }
        require(inclinationBackwardWeight in 0.0..1.0) { "inclinationBackwardWeight must be within 0…1, not $inclinationBackwardWeight" }
        require(headingSmoothing in 0.0..1.0) { "headingSmoothing must be within 0…1, not $headingSmoothing" }
        for ((name, v) in listOf(
            "smootherRestNoise" to smootherRestNoise, "smootherMotionNoise" to smootherMotionNoise,
            "smootherHeadingNoise" to smootherHeadingNoise, "smootherBiasNoise" to smootherBiasNoise,
        )) require(v.isFinite() && v > 0.0) { "$name must be finite and > 0, not $v" }
        require(smootherRestSpread > 0.0) { "smootherRestSpread must be > 0 (infinite: rest always trusted), not $smootherRestSpread" }
    }

    public companion object {
        private const val DEGREE = PI / 180.0

        /** The size of the offline replay's temporary file, bytes per output row. */
        public const val SPILL_BYTES_PER_ROW: Int = Spill.RECORD
    }
}

/**
 * The three passes around one [forward] filter (the Replayer's): as a [ReplayListener] it takes the
 * first pass's steps and reference events into the spill file; [finish] runs the other two passes and
 * hands every event on. [close] removes the file.
 */
internal class OfflinePass(private val forward: MadgwickFilter, private val offline: OfflineSettings, tempDir: Path?) : ReplayListener, Closeable {
    private val spill = Spill(tempDir)
    private val maxGapNs = (forward.settings.maxGap * 1e9).toLong()
    private val field = FieldReference(forward.settings)
    // The heading smoother uses the magnetometer, so not in IMU mode (where the passes leave it out).
    private val smoother = if (offline.headingSmoothing > 0.0 && forward.settings.mode == FilterMode.MARG) HeadingSmoother(offline) else null

    override fun step(step: ReplayStep) {
        var flags = 0L
        if (fresh(step.timestampNs, step.accelerometerNs)) flags = flags or ACC_FRESH
        if (fresh(step.timestampNs, step.magnetometerNs)) {
            flags = flags or MAG_FRESH
            field.add(step.magneticField, step.orientation, forward.atRest)
        }
        spill.putStep(flags, step.timestampNs, step.timeS, step.angularVelocity, step.specificForce, step.magneticField, step.orientation)
    }

    override fun reference(stream: SessionStream, timestampNs: Long, values: DoubleArray) =
        spill.putReference(stream.ordinal, timestampNs, values, minOf(stream.valueCount, values.size, Spill.MAX_VALUES))

    private fun fresh(t: Long, sampleNs: Long) = sampleNs != Long.MIN_VALUE && t - sampleNs <= maxGapNs

    /** The backward pass, then the second forward pass to [listener]. */
    fun finish(listener: ReplayListener) {
        spill.endWriting()
        val n = spill.records
        if (n == 0L) return
        val settings = forward.settings
        // Backward: time runs as −t, so that it advances.
        val back = MadgwickFilter(settings)
        back.restore(forward.state())
        back.turnAround(reversed(spill.lastStepNs))
        val q = DoubleArray(4)
        // A gyroscope reading is the rate over the interval that ends at its timestamp (the forward
        // step's rule), so going back from t_{i+1} to t_i integrates the reading of t_{i+1}; the last
        // record needs no step (the state is already there).
        var gx = Double.NaN
        var gy = Double.NaN
        var gz = Double.NaN
        var pending = false
        var later = Long.MIN_VALUE
        field.settle()
        val trustRest = field.motionSpread <= offline.smootherRestSpread
        // How recently, on this pass's clock, the field was disturbed: 1 then, decaying at the heading gain.
        var backRecent = 0.0
        val mb = DoubleArray(3)
        val gb = DoubleArray(3)
        spill.backward { b, at ->
            val flags = b.getLong(at)
            if (flags and REFERENCE != 0L) return@backward
            val ns = b.getLong(at + 8)
            val t = reversed(ns)
            if (flags and ACC_FRESH != 0L) back.updateAccelerometer(t, b.getDouble(at + Spill.ACC), b.getDouble(at + Spill.ACC + 8), b.getDouble(at + Spill.ACC + 16))
            if (flags and MAG_FRESH != 0L) back.updateMagnetometer(t, b.getDouble(at + Spill.MAG), b.getDouble(at + Spill.MAG + 8), b.getDouble(at + Spill.MAG + 16))
            if (pending) back.updateGyroscope(t, -gx, -gy, -gz)
            // Across a gap the backward pass goes on from the forward pass's orientation at its near side
            // (the forward pass ran through the samples before the gap; what this pass carries over it is a guess).
            val gap = later != Long.MIN_VALUE && later - ns > maxGapNs
            if (gap) takeOver(back, b, at, q)
            if (later != Long.MIN_VALUE) backRecent = field.decay(backRecent, later - ns)
            val stepS = if (later != Long.MIN_VALUE) (later - ns) * 1e-9 else 0.0
            later = ns
            val hx = -gx
            val hy = -gy
            val hz = -gz
            val linked = pending && !gap
            gx = b.getDouble(at + Spill.GYRO); gy = b.getDouble(at + Spill.GYRO + 8); gz = b.getDouble(at + Spill.GYRO + 16)
            pending = true
            if (back.isInitialised) back.orientationInto(q) else q.fill(Double.NaN)
            for (k in 0 until 4) b.putDouble(at + Spill.Q + 8 * k, q[k])
            var disturbed = false
            if (flags and MAG_FRESH != 0L) {
                for (k in 0 until 3) mb[k] = b.getDouble(at + Spill.MAG + 8 * k)
                disturbed = field.disturbed(mb, q)
                if (disturbed) backRecent = 1.0
            }
            b.putDouble(at + Spill.RECENT, backRecent)
            if (smoother != null) {
                back.gyroBiasInto(gb)
                smoother.filterStep(b, at, q, linked, hx - gb[0], hy - gb[1], hz - gb[2], stepS, flags and MAG_FRESH != 0L, mb, back.atRest && trustRest, disturbed)
            }
        }
        // Forward again, from where the backward pass ended.
        val again = MadgwickFilter(settings)
        again.restore(back.state())
        again.turnAround(spill.firstStepNs)
        val step = ReplayStep()
        val values = DoubleArray(Spill.MAX_VALUES)
        val w0 = offline.backwardWeight
        val wi = offline.inclinationBackwardWeight
        var earlier = Long.MIN_VALUE
        var foreRecent = 0.0
        spill.forward { b, at ->
            val flags = b.getLong(at)
            val t = b.getLong(at + 8)
            if (flags and REFERENCE != 0L) {
                val count = (flags ushr 16).toInt() and 0xFF
                for (k in 0 until count) values[k] = b.getDouble(at + Spill.VALUES + 8 * k)
                listener.reference(STREAMS[(flags ushr 8).toInt() and 0xFF], t, values)
                return@forward
            }
            val g = step.angularVelocity
            val a = step.specificForce
            val m = step.magneticField
            for (k in 0 until 3) {
                g[k] = b.getDouble(at + Spill.GYRO + 8 * k)
                a[k] = b.getDouble(at + Spill.ACC + 8 * k)
                m[k] = b.getDouble(at + Spill.MAG + 8 * k)
            }
            if (flags and ACC_FRESH != 0L) again.updateAccelerometer(t, a[0], a[1], a[2])
            if (flags and MAG_FRESH != 0L) again.updateMagnetometer(t, m[0], m[1], m[2])
            again.updateGyroscope(t, g[0], g[1], g[2])
            // Across a gap, on from the backward pass's orientation at its far side (as the backward pass did).
            if (earlier != Long.MIN_VALUE && t - earlier > maxGapNs) takeOver(again, b, at, q)
            if (earlier != Long.MIN_VALUE) foreRecent = field.decay(foreRecent, t - earlier)
            earlier = t
            val o = step.orientation
            if (again.isInitialised) again.orientationInto(o) else o.fill(Double.NaN)
            if (flags and MAG_FRESH != 0L && field.disturbed(m, o)) foreRecent = 1.0
            for (k in 0 until 4) q[k] = b.getDouble(at + Spill.Q + 8 * k)
            combine(o, q, headingWeight(w0, foreRecent, b.getDouble(at + Spill.RECENT)), wi)
            if (smoother != null && smoother.smoothStep(b, at, t, q)) combine(o, q, offline.headingSmoothing, 0.0)
            step.timestampNs = t
            step.timeS = b.getDouble(at + Spill.TIME)
            step.initialised = !o[0].isNaN()
            listener.step(step)
        }
    }

    /** [filter] takes the orientation stored in the record at [at] (the other pass's), if it has one; [q] is scratch. */
    private fun takeOver(filter: MadgwickFilter, b: ByteBuffer, at: Int, q: DoubleArray) {
        for (k in 0 until 4) q[k] = b.getDouble(at + Spill.Q + 8 * k)
        if (filter.isInitialised && !q[0].isNaN()) filter.takeOrientation(q)
    }

    override fun close() = spill.close()

    companion object {
        private val STREAMS = SessionStream.values()
        const val REFERENCE = 1L
        const val ACC_FRESH = 2L
        const val MAG_FRESH = 4L

        /**
         * The backward pass's weight in the heading, from [w0] (its weight where neither pass has met a
         * disturbed field lately) and how recently each pass met one ([forward], [backward]: 1 just then,
         * towards 0 as the heading correction has pulled the error out): each pass's confidence, (1 − w0) or
         * w0, shrinks by that factor (down to a floor), and the weight is the backward one's share.
         */
        fun headingWeight(w0: Double, forward: Double, backward: Double): Double {
            val f = (1.0 - w0) * (1.0 - forward) + CONFIDENCE_FLOOR
            val b = w0 * (1.0 - backward) + CONFIDENCE_FLOOR
            return b / (f + b)
        }

        /** The least confidence a pass keeps, so that where both met a disturbance lately the weights stay defined. */
        const val CONFIDENCE_FLOOR = 0.05

        /** The backward pass's clock: −t (Long.MIN_VALUE, whose negation does not exist, as Long.MAX_VALUE). */
        fun reversed(t: Long) = if (t == Long.MIN_VALUE) Long.MAX_VALUE else -t

        /**
         * p ← p turned towards q (unit quaternions, sensor → world) by the fraction [wh] of the rotation
         * between them about the world's vertical (heading) and by [wi] of the rotation about the horizontal
         * axes (inclination): with e = q ⊗ p* (the sign taken with e_w ≥ 0), e' = [e_w, wi·e_x, wi·e_y, wh·e_z]
         * normalised, p ← e' ⊗ p. For wh = wi = w the result lies on the arc from p to q, at tan(θ'/2) =
         * w·tan(θ/2) for the angle θ between them (for estimates a few degrees apart slerp by w to within
         * 10⁻³ of θ). Where one is NaN, the other.
         */
        fun combine(p: DoubleArray, q: DoubleArray, wh: Double, wi: Double) {
            if (q[0].isNaN()) return
            if (p[0].isNaN()) {
                q.copyInto(p)
                return
            }
            val p0 = p[0]
            val p1 = p[1]
            val p2 = p[2]
            val p3 = p[3]
            var e0 = q[0] * p0 + q[1] * p1 + q[2] * p2 + q[3] * p3
            var e1 = -q[0] * p1 + q[1] * p0 - q[2] * p3 + q[3] * p2
            var e2 = -q[0] * p2 + q[1] * p3 + q[2] * p0 - q[3] * p1
            var e3 = -q[0] * p3 - q[1] * p2 + q[2] * p1 + q[3] * p0
            if (e0 < 0.0) {
                e0 = -e0; e1 = -e1; e2 = -e2; e3 = -e3
            }
            e1 *= wi; e2 *= wi; e3 *= wh
            val r0 = e0 * p0 - e1 * p1 - e2 * p2 - e3 * p3
            val r1 = e0 * p1 + e1 * p0 + e2 * p3 - e3 * p2
            val r2 = e0 * p2 - e1 * p3 + e2 * p0 + e3 * p1
            val r3 = e0 * p3 + e1 * p2 - e2 * p1 + e3 * p0
            val inv = 1.0 / sqrt(r0 * r0 + r1 * r1 + r2 * r2 + r3 * r3)
            p[0] = r0 * inv; p[1] = r1 * inv; p[2] = r2 * inv; p[3] = r3 * inv
        }
    }
}

/**
 * The heading smoother of the offline estimate: a Kalman filter over the whole recording, then a
 * Rauch–Tung–Striebel pass back over it, on two numbers: x, the heading correction (rad, a turn about
 * the world's vertical applied on the left) of the backward pass's orientation, and b, what is left of
 * the gyroscope's bias about the vertical (rad/s) after the filter's own estimate. From one step to the
 * next x changes by u − b·Δt, u the heading correction the backward pass's own step made (−1 × the turn
 * about the vertical between its new orientation and where the gyroscope alone would have taken it),
 * so x follows the gyroscope, and b lets the gyroscope drift steadily between two stretches where the
 * magnetometer is trusted. Each fresh magnetometer reading measures x (the turn that brings its
 * horizontal part onto north) with a variance of [OfflineSettings.smootherRestNoise]² / Δt at rest (the
 * rest detector's flag, where the field holds steady in motion: [OfflineSettings.smootherRestSpread]) and
 * [OfflineSettings.smootherMotionNoise]² / Δt in motion; a reading the field check finds disturbed
 * ([FieldReference]) is left out. So where a recording rests, the heading is pinned there and the
 * gyroscope's drift between rests is taken out, and the magnetometer in motion, which the rest of the
 * estimate follows, counts little.
 *
 * The filter runs in the backward pass (its own time order, the recording's backward) and keeps each
 * record's filtered state (x, b and their covariance, and u) in the spill file; the smoothing runs in the
 * second forward pass from that. State: a few doubles, whatever the length. Across a gap the filter starts
 * again (the backward pass took another orientation there).
 */
internal class HeadingSmoother(s: OfflineSettings) {
    private val rRest = s.smootherRestNoise * s.smootherRestNoise
    private val rMotion = s.smootherMotionNoise * s.smootherMotionNoise
    private val qx = s.smootherHeadingNoise * s.smootherHeadingNoise
    private val qb = s.smootherBiasNoise * s.smootherBiasNoise
    private var x = 0.0
    private var b = 0.0
    private var p11 = 0.0
    private var p12 = 0.0
    private var p22 = 0.0
    private var started = false
    private val prev = DoubleArray(4)

    // The smoothing pass: the previous record's smoothed state and its increment.
    private var xs = Double.NaN
    private var bs = 0.0
    private var prevU = Double.NaN
    private var prevNs = 0L

    private fun start() {
        x = 0.0; b = 0.0
        p11 = X0 * X0; p12 = 0.0; p22 = B0 * B0
        started = true
    }

    /** One step of the filter at the record at [at]: orientation [q], rate (bias-corrected) of the step into it. */
    fun filterStep(buf: ByteBuffer, at: Int, q: DoubleArray, linked: Boolean, wx: Double, wy: Double, wz: Double, dt: Double,
                   magFresh: Boolean, m: DoubleArray, rest: Boolean, disturbed: Boolean) {
        var u = Double.NaN
        if (q[0].isNaN()) {
            started = false
        } else {
            if (!started || !linked) {
                start()
            } else {
                // Where the gyroscope alone would have taken the previous orientation, p; the correction c = q ⊗ p*.
                val h = 0.5 * dt
                val p0 = prev[0] + h * (-prev[1] * wx - prev[2] * wy - prev[3] * wz)
                val p1 = prev[1] + h * (prev[0] * wx + prev[2] * wz - prev[3] * wy)
                val p2 = prev[2] + h * (prev[0] * wy - prev[1] * wz + prev[3] * wx)
                val p3 = prev[3] + h * (prev[0] * wz + prev[1] * wy - prev[2] * wx)
                val cw = q[0] * p0 + q[1] * p1 + q[2] * p2 + q[3] * p3
                val cz = -q[0] * p3 - q[1] * p2 + q[2] * p1 + q[3] * p0
                u = -2.0 * atan(cz / cw)
                // A reading the filter skipped (not finite): the step's turn is unknown, so x carries on unchanged
                // and only its uncertainty grows; a NaN here would otherwise stay in x to the start of the pass.
                if (!u.isFinite()) u = 0.0
                x += u - b * dt
                val n11 = p11 - 2.0 * dt * p12 + dt * dt * p22 + qx * dt
                val n12 = p12 - dt * p22
                p22 += qb * dt
                p11 = n11; p12 = n12
            }
            if (magFresh && dt > 0.0 && !disturbed && usable(m)) {
                // The reading's measure of x, its variance, and the update (P ← (I − K H) P, H = [1, 0]).
                val r = (if (rest) rRest else rMotion) / dt
                val e = wrap(magHeading(m, q) - x)
                val sInv = 1.0 / (p11 + r)
                val k1 = p11 * sInv
                val k2 = p12 * sInv
                x += k1 * e; b += k2 * e
                p22 -= k2 * p12
                p11 *= 1.0 - k1
                p12 *= 1.0 - k1
            }
            q.copyInto(prev)
        }
        buf.putDouble(at + Spill.KX, if (started) x else Double.NaN)
        buf.putDouble(at + Spill.KB, b)
        buf.putDouble(at + Spill.KP11, p11)
        buf.putDouble(at + Spill.KP12, p12)
        buf.putDouble(at + Spill.KP22, p22)
        buf.putDouble(at + Spill.KU, u)
    }

    /** The smoothed correction at the record at [at] (time [ns]) applied to [q] (the backward pass's orientation); false where there is none. */
    fun smoothStep(buf: ByteBuffer, at: Int, ns: Long, q: DoubleArray): Boolean {
        val xk = buf.getDouble(at + Spill.KX)
        val u = buf.getDouble(at + Spill.KU)
        if (xk.isNaN()) {
            xs = Double.NaN
            prevU = u
            prevNs = ns
            return false
        }
        val bk = buf.getDouble(at + Spill.KB)
        if (xs.isNaN() || prevU.isNaN()) {
            xs = xk; bs = bk
        } else {
            val a11 = buf.getDouble(at + Spill.KP11)
            val a12 = buf.getDouble(at + Spill.KP12)
            val a22 = buf.getDouble(at + Spill.KP22)
            val dt = (ns - prevNs) * 1e-9
            // The prediction from this record to the previous one (the filter's order), and the gain.
            val xp = xk + prevU - bk * dt
            val pp11 = a11 - 2.0 * dt * a12 + dt * dt * a22 + qx * dt
            val pp12 = a12 - dt * a22
            val pp22 = a22 + qb * dt
            // P F^T
            val f11 = a11 - dt * a12
            val f12 = a12
            val f21 = a12 - dt * a22
            val f22 = a22
            val det = pp11 * pp22 - pp12 * pp12
            val i11 = pp22 / det
            val i12 = -pp12 / det
            val i22 = pp11 / det
            val c11 = f11 * i11 + f12 * i12
            val c12 = f11 * i12 + f12 * i22
            val c21 = f21 * i11 + f22 * i12
            val c22 = f21 * i12 + f22 * i22
            val dx = wrap(xs - xp)
            val db = bs - bk
            xs = xk + c11 * dx + c12 * db
            bs = bk + c21 * dx + c22 * db
        }
        prevU = u
        prevNs = ns
        // q ← Rz(xs) ⊗ q
        val c = cos(0.5 * xs)
        val s = sin(0.5 * xs)
        val q0 = c * q[0] - s * q[3]
        val q1 = c * q[1] - s * q[2]
        val q2 = c * q[2] + s * q[1]
        val q3 = c * q[3] + s * q[0]
        q[0] = q0; q[1] = q1; q[2] = q2; q[3] = q3
        return true
    }

    companion object {
        /** The filter's start: x and b unknown within 5° and 0.2°/s (a standard deviation). */
        const val X0 = 5.0 * PI / 180.0
        const val B0 = 0.2 * PI / 180.0

        fun wrap(a: Double): Double = if (a > PI) a - 2 * PI else if (a < -PI) a + 2 * PI else a

        /** A magnetometer reading that can measure the heading: finite, not zero (an empty field of a table is NaN), no stronger than the earth's. */
        fun usable(m: DoubleArray): Boolean = SensorRanges.isEarthField(m[0], m[1], m[2])

        /** The correction about the vertical (rad) that turns [q] (sensor → ENU) so that the field [m] points north. */
        fun magHeading(m: DoubleArray, q: DoubleArray): Double {
            val w = q[0]; val x = q[1]; val y = q[2]; val z = q[3]
            val e = (1 - 2 * (y * y + z * z)) * m[0] + 2 * (x * y - w * z) * m[1] + 2 * (x * z + w * y) * m[2]
            val n = 2 * (x * y + w * z) * m[0] + (1 - 2 * (x * x + z * z)) * m[1] + 2 * (y * z - w * x) * m[2]
            return atan2(e, n)
        }
    }
}

/**
 * The recording's own undisturbed field, for the offline combination: the medians of the magnetometer's
 * magnitude (µT) and dip angle (the angle below the horizontal, from the first pass's orientation) over the
 * whole recording, kept as histograms (memory fixed whatever the length). A reading is disturbed when its
 * magnitude departs from that median by more than FilterSettings.magNormTolerance (relative) or its dip, by
 * the orientation given, by more than magDipTolerance: the causal filter's own tolerances. It also keeps the
 * magnitudes read while the device moves (the first pass's rest detector), for [motionSpread]. Frames: field
 * in the device frame, orientation sensor → ENU.
 */
internal class FieldReference(settings: dev.motionfusion.core.filter.FilterSettings) {
    private val normTolerance = settings.magNormTolerance
    private val dipTolerance = settings.magDipTolerance

    /** The rate at which the heading correction pulls an error out, 1/s (headingGain; the default's with the report's step). */
    private val rate = if (settings.headingGain > 0.0) settings.headingGain else DEFAULT_RATE
    private val norms = IntArray(NORM_BINS)
    private val motionNorms = IntArray(NORM_BINS)
    private var motionCount = 0L

    /**
     * The spread of the field's magnitude while the device moved: 1.4826 × its median absolute deviation, relative
     * to its median (so a standard deviation for normal noise); 0 without such readings. Set by [settle].
     */
    var motionSpread = 0.0
        private set

    // Sines of the dip (monotonic in the dip, so their median is the sine of the median dip): no arcsine per reading.
    private val sinDips = IntArray(SIN_BINS)
    private var count = 0L
    private var normLow = Double.NaN
    private var normHigh = Double.NaN
    private var sinLow = Double.NaN
    private var sinHigh = Double.NaN
    private var decayNs = -1L
    private var decayFactor = 1.0

    /** Takes the reading [m] at the orientation [q]; [rest]: the rest detector's flag then. */
    fun add(m: DoubleArray, q: DoubleArray, rest: Boolean) {
        if (!SensorRanges.isEarthField(m[0], m[1], m[2]) || q[0].isNaN()) return
        val n = sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2])
        val bin = (n / NORM_BIN).toInt().coerceIn(0, NORM_BINS - 1)
        norms[bin]++
        if (!rest) {
            motionNorms[bin]++
            motionCount++
        }
        sinDips[((sinDip(m, n, q) + 1.0) / SIN_BIN).toInt().coerceIn(0, SIN_BINS - 1)]++
        count++
    }

    /** Fixes the medians and the limits around them; before any reading was added nothing is disturbed. */
    fun settle() {
        if (count == 0L) return
        if (motionCount > 0L) {
            // The median absolute deviation from the histogram: the deviations' histogram in the same bins.
            val mid = median(motionNorms, motionCount)
            val deviations = IntArray(NORM_BINS)
            for (i in motionNorms.indices) if (motionNorms[i] != 0) deviations[abs(i - mid)] += motionNorms[i]
            motionSpread = MAD_TO_SD * median(deviations, motionCount) / (mid + 0.5)
        }
        val norm = (median(norms, count) + 0.5) * NORM_BIN
        normLow = norm * (1.0 - normTolerance)
        normHigh = norm * (1.0 + normTolerance)
        val dip = asin(((median(sinDips, count) + 0.5) * SIN_BIN - 1.0).coerceIn(-1.0, 1.0))
        sinLow = sin(maxOf(-PI / 2, dip - dipTolerance))
        sinHigh = sin(minOf(PI / 2, dip + dipTolerance))
    }

    fun disturbed(m: DoubleArray, q: DoubleArray): Boolean {
        if (normLow.isNaN() || q[0].isNaN()) return false
        val n = sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2])
        if (!(n > 0.0) || n.isInfinite()) return false
        if (n < normLow || n > normHigh) return true
        val s = sinDip(m, n, q)
        return s < sinLow || s > sinHigh
    }

    /** [recent] after [ns] more of a pass without a disturbed reading (0 once below 10⁻⁴). */
    fun decay(recent: Double, ns: Long): Double {
        if (recent == 0.0) return 0.0
        if (ns != decayNs) {
            decayNs = ns
            decayFactor = exp(-rate * ns * 1e-9)
        }
        val r = recent * decayFactor
        return if (r < 1e-4) 0.0 else r
    }

    private fun median(h: IntArray, count: Long): Int {
        var seen = 0L
        for (i in h.indices) {
            seen += h[i]
            if (2 * seen >= count) return i
        }
        return h.size - 1
    }

    companion object {
        const val NORM_BIN = 0.1
        const val NORM_BINS = 20_000
        const val SIN_BINS = 4000
        const val SIN_BIN = 2.0 / SIN_BINS
        const val DEFAULT_RATE = 0.05

        /** A normal distribution's standard deviation over its median absolute deviation. */
        const val MAD_TO_SD = 1.4826

        /** Sine of the dip angle: of [m] (magnitude [n]) below the horizontal of the orientation [q] (sensor → ENU). */
        fun sinDip(m: DoubleArray, n: Double, q: DoubleArray): Double {
            // Up in the sensor frame: the third row of R(q).
            val ux = 2.0 * (q[1] * q[3] - q[0] * q[2])
            val uy = 2.0 * (q[2] * q[3] + q[0] * q[1])
            val uz = 1.0 - 2.0 * (q[1] * q[1] + q[2] * q[2])
            return -(m[0] * ux + m[1] * uy + m[2] * uz) / n
        }
    }
}

/**
 * Fixed-size binary records in a temporary file, written in order and then read backward (each
 * block written back after it) and forward, a block at a time: memory is two blocks whatever the
 * length. The file is unlinked as soon as it is open where the system allows it (then nothing is
 * left behind even if the process is killed); elsewhere it is removed by [close], at exit, and by
 * a shutdown hook on an interrupt.
 *
 * A record, 184 bytes: flags (kind, and for a reference its stream and value count), timestamp ns,
 * then for a step t_s, gyroscope (3), accelerometer (3), magnetometer (3), orientation (4: the first
 * pass's, then the backward pass's), how recently the backward pass met a disturbed field and the
 * heading smoother's filtered state (x, b, the covariance's three terms, u); for a reference up to
 * [MAX_VALUES] values.
 */
internal class Spill(dir: Path?) : Closeable {
    private val path: Path = if (dir == null) Files.createTempFile("fusion-offline-", ".tmp") else Files.createTempFile(dir, ".fusion-offline-", ".tmp")
    val channel: FileChannel
    val block: ByteBuffer = ByteBuffer.allocateDirect(RECORD * BLOCK).order(ByteOrder.nativeOrder())

    /** The same buffer as a java.nio.Buffer (Android 8 has no ByteBuffer overrides of flip, clear, position, limit). */
    val buffer: Buffer = block
    private var unlinked = false
    private var closed = false

    /** Records written. */
    var records = 0L
        private set
    var firstStepNs = Long.MIN_VALUE
        private set
    var lastStepNs = Long.MIN_VALUE
        private set

    init {
        try {
            channel = FileChannel.open(path, StandardOpenOption.READ, StandardOpenOption.WRITE)
        } catch (e: Throwable) {
            Files.deleteIfExists(path)
            throw e
        }
        unlinked = try {
            Files.delete(path)
            true
        } catch (e: IOException) {
            false
        }
        if (!unlinked) {
            path.toFile().deleteOnExit()
            TemporaryFiles.add(path)
        }
    }

    /** Runs [block]; a failure to write the spill names its folder (the file itself may be unlinked) and the reason. */
    inline fun <T> named(block: () -> T): T = try {
        block()
    } catch (e: IOException) {
        throw java.nio.file.FileSystemException(
            folder, null,
            "the offline estimate's temporary file (java.io.tmpdir; give it room, or another folder with -Djava.io.tmpdir=DIR): ${AtomicFiles.reason(e)}",
        ).apply { initCause(e) }
    }

    /** The folder of the spill, for messages. */
    val folder: String = path.toAbsolutePath().parent.toString()

    private fun room() {
        if (block.position() == block.capacity()) {
            buffer.flip()
            named { while (block.hasRemaining()) channel.write(block) }
            buffer.clear()
        }
    }

    fun putStep(flags: Long, t: Long, timeS: Double, g: DoubleArray, a: DoubleArray, m: DoubleArray, q: DoubleArray) {
        room()
        val at = block.position()
        block.putLong(at, flags).putLong(at + 8, t).putDouble(at + TIME, timeS)
        for (k in 0 until 3) {
            block.putDouble(at + GYRO + 8 * k, g[k]).putDouble(at + ACC + 8 * k, a[k]).putDouble(at + MAG + 8 * k, m[k])
        }
        for (k in 0 until 4) block.putDouble(at + Q + 8 * k, q[k])
        buffer.position(at + RECORD)
        records++
        if (firstStepNs == Long.MIN_VALUE) firstStepNs = t
        lastStepNs = t
    }

    fun putReference(stream: Int, t: Long, values: DoubleArray, count: Int) {
        room()
        val at = block.position()
        block.putLong(at, OfflinePass.REFERENCE or (stream.toLong() shl 8) or (count.toLong() shl 16)).putLong(at + 8, t)
        for (k in 0 until count) block.putDouble(at + VALUES + 8 * k, values[k])
        buffer.position(at + RECORD)
        records++
    }

    fun endWriting() {
        buffer.flip()
        named { while (block.hasRemaining()) channel.write(block) }
        buffer.clear()
    }

    /** [visit] (block, offset of the record) for every record from the last to the first; changes are written back. */
    inline fun backward(visit: (ByteBuffer, Int) -> Unit) {
        var end = records
        while (end > 0) {
            val start = maxOf(0L, end - BLOCK)
            val n = (end - start).toInt()
            read(start, n)
            for (i in n - 1 downTo 0) visit(block, i * RECORD)
            buffer.position(0).limit(n * RECORD)
            var pos = start * RECORD
            named { while (block.hasRemaining()) pos += channel.write(block, pos) }
            end = start
        }
        buffer.clear()
    }

    /** [visit] (block, offset of the record) for every record from the first to the last. */
    inline fun forward(visit: (ByteBuffer, Int) -> Unit) {
        var start = 0L
        while (start < records) {
            val n = minOf(BLOCK.toLong(), records - start).toInt()
            read(start, n)
            for (i in 0 until n) visit(block, i * RECORD)
            start += n
        }
        buffer.clear()
    }

    fun read(start: Long, n: Int) {
        buffer.clear().limit(n * RECORD)
        var pos = start * RECORD
        while (block.hasRemaining()) {
            val r = channel.read(block, pos)
            if (r < 0) throw IOException("offline replay: the temporary file ended early")
            pos += r
        }
    }

    override fun close() {
        if (closed) return
        closed = true
        try {
            channel.close()
        } finally {
            if (!unlinked) {
                Files.deleteIfExists(path)
                TemporaryFiles.remove(path)
            }
        }
    }

    companion object {
        const val RECORD = 184
        const val BLOCK = 2048
        const val TIME = 16
        const val GYRO = 24
        const val ACC = 48
        const val MAG = 72
        const val Q = 96
        const val RECENT = 128
        const val KX = 136
        const val KB = 144
        const val KP11 = 152
        const val KP12 = 160
        const val KP22 = 168
        const val KU = 176
        const val VALUES = 16
        const val MAX_VALUES = 14
    }
}
