/*
 * A heading tare: the replay's output frame turned about the up axis (the direction of gravity)
 * and nothing else, so that the heading reads a chosen value at a chosen moment
 * (docs/CONVENTIONS.md, "Heading tare").
 *
 * Heading ψ: the aerospace yaw of the phone (the replay CSV's yaw_deg, which is its azimuth_deg
 * away from gimbal lock): the direction of the top edge, from north toward east. A tare by Δ turns
 * the world frame by −Δ about ENU's z (up): every orientation becomes q' = r ⊗ q with
 * r = [cos(Δ/2), 0, 0, −sin(Δ/2)] ([w, x, y, z], Hamilton), still sensor → world, so every heading
 * grows by Δ (ψ' = ψ + Δ, wrapped to (−180°, 180°]) while pitch, roll and the vertical component of
 * every vector stay as they were. The world is then ENU turned about up: x, y are no longer east
 * and magnetic north but the axes whose heading is Δ and Δ + 90° less; z is still up.
 */
package dev.motionfusion.core.replay

import dev.motionfusion.core.Orientations
import dev.motionfusion.core.event.SessionStream
import kotlin.math.PI
import kotlin.math.cos
import kotlin.math.sin

/**
 * Passes each replay step to [inner] with its orientation turned about up by a heading offset:
 * [offsetRad] when given, else the one that makes the heading [headingRad] at the first step with
 * an orientation ([atStart]). The step's orientation array is changed in place (every listener
 * after this one sees the tared orientation). Reference streams pass unchanged.
 */
public class HeadingTare private constructor(
    private val inner: ReplayListener,
    offsetRad: Double,
    private val headingRad: Double,
) : ReplayListener {
    /** The offset Δ applied, radians (NaN until the first orientation when it is taken there). */
    public var offsetRad: Double = offsetRad
        private set

    private val angles = DoubleArray(6)
    private var rw = Double.NaN
    private var rz = Double.NaN

    init {
        if (offsetRad.isFinite()) setOffset(offsetRad)
    }

    private fun setOffset(d: Double) {
        offsetRad = wrap(d)
        rw = cos(offsetRad / 2)
        rz = -sin(offsetRad / 2)
    }

    override fun step(step: ReplayStep) {
        if (step.initialised) {
            if (offsetRad.isNaN()) setOffset(headingRad - heading(step.orientation, angles))
            val q = step.orientation
            // r ⊗ q with r = [rw, 0, 0, rz].
            val w = rw * q[0] - rz * q[3]
            val x = rw * q[1] - rz * q[2]
            val y = rw * q[2] + rz * q[1]
            val z = rw * q[3] + rz * q[0]
            q[0] = w; q[1] = x; q[2] = y; q[3] = z
        }
        inner.step(step)
    }

    override fun reference(stream: SessionStream, timestampNs: Long, values: DoubleArray): Unit = inner.reference(stream, timestampNs, values)

    public companion object {
        /** Every heading grows by [offsetRad]. */
        @JvmStatic
        public fun offset(inner: ReplayListener, offsetRad: Double): HeadingTare {
            require(offsetRad.isFinite()) { "heading offset must be finite" }
            return HeadingTare(inner, offsetRad, Double.NaN)
        }

        /** The heading is [headingRad] at the first step with an orientation (the filter's start). */
        @JvmStatic
        public fun atStart(inner: ReplayListener, headingRad: Double): HeadingTare {
            require(headingRad.isFinite()) { "heading must be finite" }
            return HeadingTare(inner, Double.NaN, headingRad)
        }

        /** The heading ψ (radians, (−π, π]) of [q] (sensor → ENU): the aerospace yaw of the phone. */
        @JvmStatic
        public fun heading(q: DoubleArray): Double = heading(q, DoubleArray(6))

        private fun heading(q: DoubleArray, angles: DoubleArray): Double {
            Orientations.androidAndAerospaceAngles(q, angles, 0)
            return angles[3]
        }

        /** [a] in (−π, π]. */
        private fun wrap(a: Double): Double {
            var r = a % (2 * PI)
            if (r <= -PI) r += 2 * PI
            if (r > PI) r -= 2 * PI
            return r
        }
    }
}

/** Finds the heading of the first step with an orientation at or after [atS] (seconds since the recording's origin): [headingRad], NaN while none. */
public class HeadingProbe(private val atS: Double) : ReplayListener {
    public var headingRad: Double = Double.NaN
        private set

    /** The time of that step, s (NaN while none). */
    public var timeS: Double = Double.NaN
        private set

    override fun step(step: ReplayStep) {
        if (headingRad.isNaN() && step.initialised && step.timeS >= atS) {
            headingRad = HeadingTare.heading(step.orientation)
            timeS = step.timeS
        }
    }
}

/**
 * A heading tare as asked for: a fixed [offsetDeg] added to every heading, or the heading made
 * [headingDeg] at [atS] (seconds of the output's t_s; null: the filter's first orientation).
 * [offsetRad] turns it into the offset of [HeadingTare], by a first replay where it needs one.
 */
public class HeadingTareSpec private constructor(public val offsetDeg: Double?, public val atS: Double?, public val headingDeg: Double) {
    /**
     * The offset Δ, radians: [offsetDeg], else the one that makes the heading [headingDeg] at [atS], found by
     * [replay] (a replay of the recording into the listener it is given). [source] names the recording in errors.
     * @throws dev.motionfusion.core.io.DataFormatException when the filter has no orientation at or after [atS].
     */
    public fun offsetRad(source: String, replay: (ReplayListener) -> Unit): Double {
        if (offsetDeg != null) return Math.toRadians(offsetDeg)
        val probe = HeadingProbe(atS ?: Double.NEGATIVE_INFINITY)
        replay(probe)
        if (probe.headingRad.isNaN()) {
            throw dev.motionfusion.core.io.DataFormatException(
                source, 0, 0,
                if (atS == null) "the filter gives no orientation: no heading to tare" else "heading tare at ${fmt(atS)} s: the filter has no orientation at or after t = ${fmt(atS)} s",
            )
        }
        return Math.toRadians(headingDeg) - probe.headingRad
    }

    /** How an output names its frame once the tare [appliedDeg] is known. */
    public fun describe(appliedDeg: Double): String =
        "ENU turned about up (heading tare: every heading + ${fmt(appliedDeg)} deg${if (offsetDeg == null) ", so that it reads ${fmt(headingDeg)} deg at ${atS?.let { "t = ${fmt(it)} s" } ?: "the first orientation"}" else ""})"

    public companion object {
        /** Every heading grows by [deg]. */
        @JvmStatic
        public fun offset(deg: Double): HeadingTareSpec {
            require(deg.isFinite()) { "heading offset must be finite" }
            return HeadingTareSpec(deg, null, 0.0)
        }

        /** The heading reads [headingDeg] at [atS] s (null: the first orientation); zero at the start: `at(null, 0.0)`. */
        @JvmStatic
        public fun at(atS: Double?, headingDeg: Double): HeadingTareSpec {
            require(headingDeg.isFinite() && (atS == null || atS.isFinite())) { "heading and time must be finite" }
            return HeadingTareSpec(null, atS, headingDeg)
        }

        /** [v] with at most 4 decimals, no trailing zeros. */
        internal fun fmt(v: Double): String = String.format(java.util.Locale.ROOT, "%.4f", v).trimEnd('0').trimEnd('.')
    }
}
