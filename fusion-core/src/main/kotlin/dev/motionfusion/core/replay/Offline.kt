/*
 * The offline estimate (`fusion replay --offline`): the orientation at each instant from the whole
 * recording, the samples after it as well as those before. One filter, three passes over the same
 * samples, all with the same settings:
 *  1. forward, as the causal replay (its counts and diagnostics are the replay's), writing each
 *     step's samples to a temporary file;
 *  2. backward in time over that file (gyroscope negated, the same accelerometer and magnetometer
 *     readings), starting from the forward pass's final state turned round (MadgwickFilter.turnAround),
 *     each step's orientation written back into the file;
 *  3. forward again, starting from the backward pass's final state (so it has converged already at
 *     the first sample), each step's orientation combined with the backward one of the same instant
 *     and handed on.
 * Both combined estimates have then seen the whole recording; their errors lag in opposite
 * directions (one integrates the past, the other the future), so the combination cancels much of
 * them. Frames and units as Replayer's.
 */
package dev.motionfusion.core.replay

import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.filter.MadgwickFilter
import java.io.Closeable
import java.io.IOException
import java.nio.Buffer
import java.nio.ByteBuffer
import java.nio.ByteOrder
import java.nio.channels.FileChannel
import java.nio.file.Files
import java.nio.file.Path
import java.nio.file.StandardOpenOption
import java.util.concurrent.ConcurrentHashMap
import kotlin.math.sqrt

/**
 * Settings of the offline estimate beyond the filter's own ([dev.motionfusion.core.filter.FilterSettings]
 * applies to every pass alike).
 *
 * @property backwardWeight weight of the backward pass's orientation in the combination, 0…1 (the
 *   second forward pass has 1 − it); chosen by cross-validation (docs/ACCURACY.md, "Offline").
 */
public data class OfflineSettings(val backwardWeight: Double = 0.3) {
    init {
        require(backwardWeight in 0.0..1.0) { "backwardWeight must be within 0…1, not $backwardWeight" }
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

    override fun step(step: ReplayStep) {
        var flags = 0L
        if (fresh(step.timestampNs, step.accelerometerNs)) flags = flags or ACC_FRESH
        if (fresh(step.timestampNs, step.magnetometerNs)) flags = flags or MAG_FRESH
        spill.putStep(flags, step.timestampNs, step.timeS, step.angularVelocity, step.specificForce, step.magneticField)
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
        back.restore(forward.snapshot())
        back.turnAround(reversed(spill.lastStepNs))
        val q = DoubleArray(4)
        // A gyroscope reading is the rate over the interval that ends at its timestamp (the forward
        // step's rule), so going back from t_{i+1} to t_i integrates the reading of t_{i+1}; the last
        // record needs no step (the state is already there).
        var gx = Double.NaN
        var gy = Double.NaN
        var gz = Double.NaN
        var pending = false
        spill.backward { b, at ->
            val flags = b.getLong(at)
            if (flags and REFERENCE != 0L) return@backward
            val t = reversed(b.getLong(at + 8))
            if (flags and ACC_FRESH != 0L) back.updateAccelerometer(t, b.getDouble(at + Spill.ACC), b.getDouble(at + Spill.ACC + 8), b.getDouble(at + Spill.ACC + 16))
            if (flags and MAG_FRESH != 0L) back.updateMagnetometer(t, b.getDouble(at + Spill.MAG), b.getDouble(at + Spill.MAG + 8), b.getDouble(at + Spill.MAG + 16))
            if (pending) back.updateGyroscope(t, -gx, -gy, -gz)
            gx = b.getDouble(at + Spill.GYRO); gy = b.getDouble(at + Spill.GYRO + 8); gz = b.getDouble(at + Spill.GYRO + 16)
            pending = true
            if (back.isInitialised) back.orientationInto(q) else q.fill(Double.NaN)
            for (k in 0 until 4) b.putDouble(at + Spill.Q + 8 * k, q[k])
        }
        // Forward again, from where the backward pass ended.
        val again = MadgwickFilter(settings)
        again.restore(back.snapshot())
        again.turnAround(spill.firstStepNs)
        val step = ReplayStep()
        val values = DoubleArray(Spill.MAX_VALUES)
        val wb = offline.backwardWeight
        val wf = 1.0 - wb
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
            val o = step.orientation
            if (again.isInitialised) again.orientationInto(o) else o.fill(Double.NaN)
            for (k in 0 until 4) q[k] = b.getDouble(at + Spill.Q + 8 * k)
            combine(o, wf, q, wb)
            step.timestampNs = t
            step.timeS = b.getDouble(at + Spill.TIME)
            step.initialised = !o[0].isNaN()
            listener.step(step)
        }
    }

    override fun close() = spill.close()

    companion object {
        private val STREAMS = SessionStream.values()
        const val REFERENCE = 1L
        const val ACC_FRESH = 2L
        const val MAG_FRESH = 4L

        /** The backward pass's clock: −t (Long.MIN_VALUE, whose negation does not exist, as Long.MAX_VALUE). */
        fun reversed(t: Long) = if (t == Long.MIN_VALUE) Long.MAX_VALUE else -t

        /**
         * p ← the weighted mean of the unit quaternions [p] (weight [wp]) and [q] (weight [wq]),
         * normalised, q's sign taken nearer p (for two estimates a few degrees apart the same as
         * slerp by wq to within 10⁻⁴ of their angle); where one is NaN, the other.
         */
        fun combine(p: DoubleArray, wp: Double, q: DoubleArray, wq: Double) {
            if (q[0].isNaN()) return
            if (p[0].isNaN()) {
                q.copyInto(p)
                return
            }
            val s = if (p[0] * q[0] + p[1] * q[1] + p[2] * q[2] + p[3] * q[3] < 0.0) -wq else wq
            val x0 = wp * p[0] + s * q[0]
            val x1 = wp * p[1] + s * q[1]
            val x2 = wp * p[2] + s * q[2]
            val x3 = wp * p[3] + s * q[3]
            val inv = 1.0 / sqrt(x0 * x0 + x1 * x1 + x2 * x2 + x3 * x3)
            p[0] = x0 * inv; p[1] = x1 * inv; p[2] = x2 * inv; p[3] = x3 * inv
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
 * A record, 128 bytes: flags (kind, and for a reference its stream and value count), timestamp ns,
 * then for a step t_s, gyroscope (3), accelerometer (3), magnetometer (3), orientation (4); for a
 * reference up to [MAX_VALUES] values.
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
            Leftovers.add(path)
        }
    }

    private fun room() {
        if (block.position() == block.capacity()) {
            buffer.flip()
            while (block.hasRemaining()) channel.write(block)
            buffer.clear()
        }
    }

    fun putStep(flags: Long, t: Long, timeS: Double, g: DoubleArray, a: DoubleArray, m: DoubleArray) {
        room()
        val at = block.position()
        block.putLong(at, flags).putLong(at + 8, t).putDouble(at + TIME, timeS)
        for (k in 0 until 3) {
            block.putDouble(at + GYRO + 8 * k, g[k]).putDouble(at + ACC + 8 * k, a[k]).putDouble(at + MAG + 8 * k, m[k])
        }
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
        while (block.hasRemaining()) channel.write(block)
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
            while (block.hasRemaining()) pos += channel.write(block, pos)
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
                Leftovers.remove(path)
            }
        }
    }

    companion object {
        const val RECORD = 128
        const val BLOCK = 2048
        const val TIME = 16
        const val GYRO = 24
        const val ACC = 48
        const val MAG = 72
        const val Q = 96
        const val VALUES = 16
        const val MAX_VALUES = 14
    }

    /** Spill files that could not be unlinked while open: removed by a shutdown hook (an interrupted run). */
    private object Leftovers {
        private val paths = ConcurrentHashMap.newKeySet<Path>()

        init {
            Runtime.getRuntime().addShutdownHook(Thread({ for (p in paths) runCatching { Files.deleteIfExists(p) } }, "offline-spill-cleanup"))
        }

        fun add(p: Path) = paths.add(p)
        fun remove(p: Path) = paths.remove(p)
    }
}
