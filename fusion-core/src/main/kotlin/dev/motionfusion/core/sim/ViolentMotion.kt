/*
 * Violent motions for the simulator: what phones go through and filters must come back from.
 *
 * Each motion occupies a window of time in which it replaces the smooth random motion and any rest
 * window. Rates are in the device frame (rad/s), accelerations in the world frame (ENU, m/s², the
 * body's acceleration, so −g on the up axis is free fall: the accelerometer then reads nothing).
 * Velocities start and end at zero where the real motion does (a drop ends on a table, a throw in a
 * hand), so the integral of the acceleration over the window is zero.
 */
package dev.motionfusion.core.sim

import dev.motionfusion.core.Vector3
import kotlin.math.PI
import kotlin.math.sin

/** The kinds of [ViolentMotion]. */
public enum class ViolentMotionKind(
    /** Length of the motion, s. */
    public val durationS: Double,
) {
    /** Dropped from 0.45 m onto a table: 0.3 s of free fall tumbling at 6 rad/s, a 25 ms impact of 12 g with a 20 rad/s bounce. */
    DROP(0.325),

    /** A person falling with the phone in a pocket: 0.8 s turning through 90° in half free fall, a 0.1 s impact of 5 g. */
    FALL(0.9),

    /** Shaken for 3 s: up to 20 rad/s about every axis and 4.5 g of acceleration along north, at about 4 Hz. */
    SHAKE(3.0),

    /** Thrown up and caught: a 0.15 s launch (the accelerometer reads 3.5 g), 0.6 s of flight spinning at 12 rad/s, a 0.15 s catch (2.5 g). */
    THROW(0.9),
}

/** A [kind] of violent motion starting at [startS] s. */
public data class ViolentMotion(val kind: ViolentMotionKind, val startS: Double) {
    init {
        require(startS.isFinite() && startS >= 0.0) { "startS must be finite and ≥ 0: $startS" }
    }

    /** Its window of time. */
    public val window: TimeWindow get() = TimeWindow(startS, startS + kind.durationS)

    /** The device-frame rate at [t] s inside the window, rad/s. */
    internal fun rate(t: Double): Vector3 {
        val u = t - startS
        return when (kind) {
            ViolentMotionKind.DROP -> if (u < DROP_FALL) Vector3(6.0, 2.0, -1.0) else Vector3(-14.0, 20.0, 5.0)
            ViolentMotionKind.FALL -> if (u < 0.8) Vector3((PI / 2) / 0.8, 0.6, -0.4) else Vector3(-3.0, 4.0, 2.0)
            ViolentMotionKind.SHAKE -> Vector3(20.0 * sin(2 * PI * 4.0 * u), 20.0 * sin(2 * PI * 4.3 * u + 1.0), 20.0 * sin(2 * PI * 3.7 * u + 2.0))
            ViolentMotionKind.THROW -> if (u in 0.15..0.75) Vector3(12.0, -4.0, 3.0) else Vector3(1.0, -0.5, 0.5)
        }
    }

    /** The world-frame (ENU) acceleration of the body at [t] s inside the window, m/s². */
    internal fun acceleration(t: Double, gravity: Double): Vector3 {
        val u = t - startS
        return when (kind) {
            // Free fall for DROP_FALL s, then the table stops the velocity g·DROP_FALL within the impact.
            ViolentMotionKind.DROP -> if (u < DROP_FALL) Vector3(0.0, 0.0, -gravity) else Vector3(0.0, 0.0, gravity * DROP_FALL / (kind.durationS - DROP_FALL))
            ViolentMotionKind.FALL -> if (u < 0.8) Vector3(0.5, 0.0, -0.5 * gravity) else Vector3(-4.0, 0.0, 0.5 * gravity * 8.0)
            ViolentMotionKind.SHAKE -> Vector3(0.0, 4.5 * gravity * sin(2 * PI * 4.0 * u), 0.0)
            ViolentMotionKind.THROW -> when {
                u < 0.15 -> Vector3(0.0, 0.0, 2.5 * gravity)
                u < 0.75 -> Vector3(0.0, 0.0, -gravity)
                else -> Vector3(0.0, 0.0, gravity * (0.6 - 0.15 * 2.5) / 0.15)
            }
        }
    }

    private companion object {
        const val DROP_FALL = 0.3
    }
}
