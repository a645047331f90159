/*
 * Magnetic disturbances for the simulator: fields that are not the earth's for a while, with truth.
 *
 * World frame ENU, µT. A disturbance gives, at a time inside its window, the field the magnetometer
 * then senses (before the sensor's own soft and hard iron): the earth's field plus a ferrous object's,
 * or a hall's own field in place of the earth's. Transitions are smooth (a raised cosine), as when a
 * phone is carried past an object or through a door; the heading the field indicates is wrong inside.
 */
package dev.motionfusion.core.sim

import dev.motionfusion.core.Vector3
import kotlin.math.PI
import kotlin.math.cos
import kotlin.math.sin

/** The kinds of [MagneticDisturbance]. */
public enum class MagneticDisturbanceKind {
    /** A ferrous object passing (a car, a radiator, a laptop): up to 40 µT added, mostly east and down, rising and falling over the window. */
    FERROUS_PASS,

    /** A steel-framed hall: inside, a weak (15 µT) field with a dip of 30° whose horizontal part points 40° west of north; 1 s transitions at the door. */
    WEAK_TILTED_HALL,
}

/** A [kind] of magnetic disturbance from [startS] for [durationS] s. */
public data class MagneticDisturbance(val kind: MagneticDisturbanceKind, val startS: Double, val durationS: Double) {
    init {
        require(startS.isFinite() && startS >= 0.0) { "startS must be finite and ≥ 0: $startS" }
        require(durationS.isFinite() && durationS >= 2.0) { "durationS must be finite and ≥ 2 s: $durationS" }
    }

    /** Its window of time. */
    public val window: TimeWindow get() = TimeWindow(startS, startS + durationS)

    /** The world-frame field at [t] s inside the window, given the earth's field [earth], µT. */
    internal fun field(t: Double, earth: Vector3): Vector3 {
        val u = t - startS
        return when (kind) {
            MagneticDisturbanceKind.FERROUS_PASS -> {
                val w = 0.5 * (1.0 - cos(2.0 * PI * u / durationS))
                earth + OBJECT_FIELD * w
            }
            MagneticDisturbanceKind.WEAK_TILTED_HALL -> {
                val w = when {
                    u < DOOR_S -> 0.5 * (1.0 - cos(PI * u / DOOR_S))
                    u > durationS - DOOR_S -> 0.5 * (1.0 - cos(PI * (durationS - u) / DOOR_S))
                    else -> 1.0
                }
                earth * (1.0 - w) + HALL_FIELD * w
            }
        }
    }

    private companion object {
        const val DOOR_S = 1.0
        val OBJECT_FIELD = Vector3(30.0, 10.0, -25.0)
        val HALL_FIELD: Vector3 = run {
            val h = 15.0 * cos(PI / 6)
            val heading = 40.0 * PI / 180.0
            // North rotated towards west by 40°: east −sin, north cos.
            Vector3(-h * sin(heading), h * cos(heading), -15.0 * sin(PI / 6))
        }
    }
}
