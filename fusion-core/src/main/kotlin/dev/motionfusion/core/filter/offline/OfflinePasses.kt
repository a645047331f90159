/*
 * The offline estimate (`fusion replay --offline`): the orientation at each instant from the whole
 * recording, the samples after it as well as those before. One filter, three passes over the same
 * samples, all with the same settings (but where the first pass finds the field straying from the gyroscope as a
 * building's does, OfflineSettings.buildingPersistence: then all three without the bias estimate in motion, the
 * first one run again over the file for the second to start from; across a gap the second still takes over the
 * first run's orientation):
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
 * The pieces apart: OfflineSettings.kt, Blend.kt (the combination), HeadingSmoother.kt, FieldReference.kt
 * (the disturbed-field check), Spill.kt (the temporary file). The replay (replay/Replayer.kt) feeds the first
 * pass's steps in and takes the rows out ([OfflineOutput]), so this package does not depend on it.
 * Frames and units as Replayer's; orientations sensor → ENU, [w, x, y, z].
 */
package dev.motionfusion.core.filter.offline

import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.filter.FilterMode
import dev.motionfusion.core.filter.FilterSettings
import dev.motionfusion.core.filter.FilterState
import dev.motionfusion.core.filter.MadgwickFilter
import java.io.Closeable
import java.nio.ByteBuffer
import java.nio.file.Path

/**
 * Where the offline estimate's rows go, in time order, from [OfflinePasses.finish]: [row] once the arrays
 * given to it hold the step's readings and orientation (NaN before the filter has one).
 */
internal interface OfflineOutput {
    fun row(timestampNs: Long, timeS: Double)

    fun reference(stream: SessionStream, timestampNs: Long, values: DoubleArray)
}

/**
 * The three passes around one [forward] filter (the Replayer's): [step] and [reference] take the first
 * pass's steps and reference events into the spill file; [finish] runs the other two passes and hands
 * every event on. [close] removes the file.
 */
internal class OfflinePasses(private val forward: MadgwickFilter, private val offline: OfflineSettings, tempDir: Path?) : Closeable {
    private val spill = Spill(tempDir)
    private val maxGapNs = (forward.settings.maxGap * 1e9).toLong()
    private val field = FieldReference(forward.settings)
    // The heading smoother uses the magnetometer, so not in IMU mode (where the passes leave it out).
    private val smoother = if (offline.headingSmoothing > 0.0 && forward.settings.mode == FilterMode.MARG) HeadingSmoother(offline) else null
    // A magnetometer reading as a pass's filter takes it (its hard-iron offset taken off).
    private val seen = DoubleArray(3)

    private fun seen(filter: MadgwickFilter, m: DoubleArray): DoubleArray {
        filter.fieldSeenInto(m, seen)
        return seen
    }

    /**
     * The first pass's step at [timestampNs] ([timeS] s from the origin): gyroscope [g], the held accelerometer
     * [a] and magnetometer [m] readings (their times [accNs], [magNs]; Long.MIN_VALUE before the first) and the
     * orientation [q] after it.
     */
    fun step(timestampNs: Long, timeS: Double, accNs: Long, magNs: Long, g: DoubleArray, a: DoubleArray, m: DoubleArray, q: DoubleArray) {
        var flags = 0L
        if (fresh(timestampNs, accNs)) flags = flags or ACC_FRESH
        if (fresh(timestampNs, magNs)) {
            flags = flags or MAG_FRESH
            field.add(seen(forward, m), q, forward.atRest)
        }
        spill.putStep(flags, timestampNs, timeS, g, a, m, q)
    }

    fun reference(stream: SessionStream, timestampNs: Long, values: DoubleArray) =
        spill.putReference(stream.ordinal, timestampNs, values, minOf(stream.valueCount, values.size, Spill.MAX_VALUES))

    private fun fresh(t: Long, sampleNs: Long) = sampleNs != Long.MIN_VALUE && t - sampleNs <= maxGapNs

    /**
     * The backward pass, then the second forward pass to [out]: before each [OfflineOutput.row], [g], [a], [m]
     * hold the step's readings and [o] its orientation. [persistenceDeg] is the first pass's judgement of the
     * field (Replayer.fieldPersistenceDeg): above [OfflineSettings.buildingPersistence] the passes run without the
     * bias estimate in motion (unless the magnetic trust is on), the first one again over the file. Returns whether
     * they did.
     */
    fun finish(g: DoubleArray, a: DoubleArray, m: DoubleArray, o: DoubleArray, out: OfflineOutput, persistenceDeg: Double): Boolean {
        spill.endWriting()
        val n = spill.records
        if (n == 0L) return false
        val fs = forward.settings
        // With the magnetic trust on, the bias estimate in motion already falls with the field's wander.
        val building = persistenceDeg > offline.buildingPersistence && fs.motionBiasGain != null && fs.headingGain != null && fs.magTrustSpread == null
        val settings = if (building) fs.copy(motionBiasGain = null) else fs
        // Backward: time runs as −t, so that it advances.
        val back = MadgwickFilter(settings)
        back.restore(if (building) forwardAgain(settings, g, a, m) else forward.state())
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
                back.fieldSeenInto(mb, mb)
                disturbed = field.disturbed(mb, q)
                if (disturbed) backRecent = 1.0
            }
            b.putDouble(at + Spill.RECENT, backRecent)
            if (smoother != null) {
                back.gyroBiasInto(gb)
                smoother.filterStep(b, at, q, linked, hx - gb[0], hy - gb[1], hz - gb[2], stepS, flags and MAG_FRESH != 0L, mb, back.atRest && trustRest, disturbed, back.magneticTrust)
            }
        }
        // Forward again, from where the backward pass ended.
        val again = MadgwickFilter(settings)
        again.restore(back.state())
        again.turnAround(spill.firstStepNs)
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
                out.reference(STREAMS[(flags ushr 8).toInt() and 0xFF], t, values)
                return@forward
            }
            stepForward(again, b, at, flags, t, g, a, m)
            // Across a gap, on from the backward pass's orientation at its far side (as the backward pass did).
            if (earlier != Long.MIN_VALUE && t - earlier > maxGapNs) takeOver(again, b, at, q)
            if (earlier != Long.MIN_VALUE) foreRecent = field.decay(foreRecent, t - earlier)
            earlier = t
            if (again.isInitialised) again.orientationInto(o) else o.fill(Double.NaN)
            if (flags and MAG_FRESH != 0L && field.disturbed(seen(again, m), o)) foreRecent = 1.0
            for (k in 0 until 4) q[k] = b.getDouble(at + Spill.Q + 8 * k)
            Blend.combine(o, q, Blend.headingWeight(w0, foreRecent, b.getDouble(at + Spill.RECENT)), wi)
            if (smoother != null && smoother.smoothStep(b, at, t, q)) Blend.combine(o, q, offline.headingSmoothing, 0.0)
            out.row(t, b.getDouble(at + Spill.TIME))
        }
        return building
    }

    /**
     * The first pass again, over the file, with [settings]: its final state. It takes the readings as the second
     * forward pass does (each held reading again at its step); [g], [a], [m] are scratch.
     */
    private fun forwardAgain(settings: FilterSettings, g: DoubleArray, a: DoubleArray, m: DoubleArray): FilterState {
        val f = MadgwickFilter(settings)
        spill.forward { b, at ->
            val flags = b.getLong(at)
            if (flags and REFERENCE == 0L) stepForward(f, b, at, flags, b.getLong(at + 8), g, a, m)
        }
        return f.state()
    }

    /** The step record at [at] ([flags], time [t]) into [filter], going forward: [g], [a], [m] then hold its readings. */
    private fun stepForward(filter: MadgwickFilter, b: ByteBuffer, at: Int, flags: Long, t: Long, g: DoubleArray, a: DoubleArray, m: DoubleArray) {
        for (k in 0 until 3) {
            g[k] = b.getDouble(at + Spill.GYRO + 8 * k)
            a[k] = b.getDouble(at + Spill.ACC + 8 * k)
            m[k] = b.getDouble(at + Spill.MAG + 8 * k)
        }
        if (flags and ACC_FRESH != 0L) filter.updateAccelerometer(t, a[0], a[1], a[2])
        if (flags and MAG_FRESH != 0L) filter.updateMagnetometer(t, m[0], m[1], m[2])
        filter.updateGyroscope(t, g[0], g[1], g[2])
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

        /** The backward pass's clock: −t (Long.MIN_VALUE, whose negation does not exist, as Long.MAX_VALUE). */
        fun reversed(t: Long) = if (t == Long.MIN_VALUE) Long.MAX_VALUE else -t
    }
}
