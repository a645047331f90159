/*
 * A simulated calibration recording, as a user following docs/CALIBRATION.md makes one: still
 * on each of the six faces in turn, then turned through every orientation.
 */
package dev.motionfusion.core.sim

import dev.motionfusion.core.Quaternion
import dev.motionfusion.core.Vector3
import kotlin.math.PI

/**
 * Parts run one after another with continuous timestamps and a continuous true orientation: for
 * each of the six faces (screen up, screen down, standing, upside down, on the left edge, on the
 * right edge) [moveS] turning at a constant rate from where the phone is onto that face, then
 * [holdS] still on it; then [turnS] turning at up to [turnRate] rad/s. The gyroscope records
 * every turn, so the recording replays like a real one. Each part is a [MotionSimulator] run of
 * [base] (its sensor errors, noise and rate) with its own seed, starting where the part before
 * ended; [base]'s duration, angular rate and rest windows are not used, and its hard iron applies
 * during its [SimulationSettings.hardIronWindow], in seconds from the start of the whole recording.
 */
public class CalibrationMotion(
    public val base: SimulationSettings,
    public val holdS: Double = 4.0,
    public val moveS: Double = 1.5,
    public val turnS: Double = 60.0,
    public val turnRate: Double = 2.5,
) {
    init {
        for ((name, v) in listOf("holdS" to holdS, "moveS" to moveS, "turnS" to turnS, "turnRate" to turnRate)) {
            require(v.isFinite() && v > 0.0) { "$name must be finite and > 0: $v" }
        }
    }

    /** Total length, s. */
    public val durationS: Double get() = FACES.size * (moveS + holdS) + turnS

    /** The parts: (the face to turn onto, or null; seconds; angular rate of the random motion). */
    private fun parts(): List<Triple<Quaternion?, Double, Double>> =
        FACES.flatMap { q -> listOf(Triple(q, moveS, 0.0), Triple(null, holdS, 0.0)) } + Triple(null, turnS, turnRate)

    /** Runs the parts, calling [action] with each sample (timestamps from 0, continuous). */
    public fun forEach(action: (SimulatedSample) -> Unit) {
        val period = (1e9 / base.rateHz).toLong()
        var t0 = 0L
        var at = base.initialOrientation
        for ((i, part) in parts().withIndex()) {
            val (face, seconds, rate) = part
            // The window in the part's own time (its samples are timed from 0).
            val start = t0 * 1e-9
            val hardIronWindow = base.hardIronWindow?.let { w -> TimeWindow(w.startS - start, maxOf(w.startS, w.endS) - start) }
            val s = base.copy(
                seed = base.seed + 1000L * (i + 1), initialOrientation = at, durationS = seconds, angularRate = rate,
                restWindows = emptyList(), hardIronWindow = hardIronWindow,
            )
            // Onto a face: the body-frame rotation from here to there, at a constant rate over the part's samples.
            val steps = maxOf(1L, (seconds * base.rateHz).toLong() - 1)
            val slew = face?.let { (at.conjugate() * it).canonical().toRotationVector() * (base.rateHz / steps) }
            var last = t0 - period
            MotionSimulator(s, slew).forEach {
                val sample = it.copy(timestampNs = t0 + it.timestampNs)
                last = sample.timestampNs
                at = sample.truth
                action(sample)
            }
            t0 = last + period
        }
    }

    private companion object {
        /** Sensor → ENU rotations that put each face down in turn (the device axis +z, −z, +y, −y, +x, −x up). */
        val FACES: List<Quaternion> = listOf(
            Quaternion.IDENTITY, Quaternion.fromAxisAngle(Vector3.UNIT_X, PI),
            Quaternion.fromAxisAngle(Vector3.UNIT_X, PI / 2), Quaternion.fromAxisAngle(Vector3.UNIT_X, -PI / 2),
            Quaternion.fromAxisAngle(Vector3.UNIT_Y, -PI / 2), Quaternion.fromAxisAngle(Vector3.UNIT_Y, PI / 2),
        )
    }
}
