/*
 * The CSV written by `fusion replay`, one row per gyroscope sample:
 *
 *   t_s,qw,qx,qy,qz,azimuth_deg,pitch_deg,roll_deg,yaw_deg,aero_pitch_deg,aero_roll_deg,
 *   lin_acc_east_m_s2,lin_acc_north_m_s2,lin_acc_up_m_s2
 *
 * q: sensor → ENU, Hamilton, scalar first (9 decimals). Android angles (degrees, 4 decimals) as
 * SensorManager.getOrientation of R(q), and aerospace angles (degrees, 4 decimals) of the phone as
 * an aircraft in North-East-Down: yaw = heading of the phone's top edge from magnetic north toward
 * east, pitch positive with the top edge up, roll positive with the right edge down; at pitch ±90°
 * roll is 0 (both from core's Orientations, where the definitions are). Linear acceleration in ENU, m/s²: R(q)·a − [0, 0, g₀] with the latest accelerometer
 * reading a and g₀ = 9.80665 (5 decimals). Rows before the filter is initialised have NaN.
 */
package dev.motionfusion.core.replay

import dev.motionfusion.core.Orientations
import dev.motionfusion.core.STANDARD_GRAVITY
import dev.motionfusion.core.io.AsciiNumbers
import dev.motionfusion.core.unitQuaternionToMatrix
import java.io.Closeable
import java.io.Flushable
import java.io.OutputStream
import java.util.concurrent.ArrayBlockingQueue

/**
 * Writes replay steps as CSV to [out] (buffered; [close] closes [out] unless [closeStream] is
 * false). With [parallel], the rows are formatted and written by a second thread while the
 * caller's thread reads and filters: the bytes are the same, in the same order (the steps are
 * handed over in batches of fixed size, so memory stays flat); a failure of [out] is thrown by
 * the next [step], [flush] or [close].
 */
public class ReplayCsvWriter @JvmOverloads constructor(
    private val out: OutputStream,
    private val closeStream: Boolean = true,
    parallel: Boolean = false,
) : ReplayListener, Closeable, Flushable {
    private val buf = ByteArray(1 shl 16)
    private var pos = 0
    private val angles = DoubleArray(9)
    private val worker: Worker? = if (parallel) Worker() else null

    /** Rows written. */
    public var rows: Long = 0L
        private set

    init {
        val h = (HEADER + "\n").toByteArray(Charsets.US_ASCII)
        h.copyInto(buf)
        pos = h.size
    }

    override fun step(step: ReplayStep) {
        val w = worker
        if (w != null) w.add(step) else format(step.timeS, step.orientation, 0, step.specificForce, 0)
        rows++
    }

    /** One row from the time, q at q[qAt..qAt+3] and the specific force at a[aAt..aAt+2]. */
    private fun format(timeS: Double, q: DoubleArray, qAt: Int, a: DoubleArray, aAt: Int) {
        if (pos + MAX_ROW > buf.size) drain()
        pos = AsciiNumbers.fixed(buf, pos, timeS, 9)
        for (k in 0 until 4) {
            buf[pos++] = COMMA
            pos = AsciiNumbers.fixed(buf, pos, q[qAt + k], 9)
        }
        derived(q, qAt, a, aAt, angles)
        // Android azimuth, pitch, roll; then the aerospace angles, which are the same numbers
        // (yaw = azimuth, pitch = −pitch, roll = roll) except at gimbal lock: their text is copied.
        val azimuth = field(angles[0], 4)
        val pitch = field(angles[1], 4)
        val roll = field(angles[2], 4)
        val rollEnd = pos
        if (angles[3] == angles[0]) copy(azimuth, pitch - 1) else field(angles[3], 4)
        if (angles[4] == -angles[1]) negated(pitch, roll - 1) else field(angles[4], 4)
        if (angles[5] == angles[2]) copy(roll, rollEnd) else field(angles[5], 4)
        for (k in 6 until 9) field(angles[k], 5)
        buf[pos++] = NL
    }

    /** Writes ",v" with [decimals]; returns where v starts. */
    private fun field(v: Double, decimals: Int): Int {
        buf[pos++] = COMMA
        val start = pos
        pos = AsciiNumbers.fixed(buf, pos, v, decimals)
        return start
    }

    /** Writes "," and the text at buf[from until to] (a field of this row), after a '-' if [minus]. */
    private fun copy(from: Int, to: Int, minus: Boolean = false) {
        var p = pos
        buf[p++] = COMMA
        if (minus) buf[p++] = MINUS
        for (i in from until to) buf[p++] = buf[i]
        pos = p
    }

    /**
     * Writes "," and the text of −v, where buf[from until to] is the text of v written by
     * [AsciiNumbers.fixed]: its sign flipped, except in "0" and "NaN", which have none.
     */
    private fun negated(from: Int, to: Int) {
        val c = buf[from]
        if (c == MINUS) copy(from + 1, to) else copy(from, to, minus = c != N && !(c == ZERO && to - from == 1))
    }

    private fun drain() {
        out.write(buf, 0, pos)
        pos = 0
    }

    override fun flush() {
        val w = worker
        if (w != null) {
            w.sync(Batch.FLUSH)
        } else {
            drain()
            out.flush()
        }
    }

    override fun close() {
        try {
            val w = worker
            if (w != null) w.sync(Batch.END) else flush()
        } finally {
            if (closeStream) out.close()
        }
    }

    /** Steps handed over: t, q (4), specific force (3) per row. */
    private class Batch(val data: DoubleArray) {
        var count = 0

        companion object {
            const val ROWS = 4096
            const val STRIDE = 8
            const val FLUSH = -1
            const val END = -2
        }
    }

    /** The formatting thread and the two queues of batches between it and the caller. */
    private inner class Worker {
        private val free = ArrayBlockingQueue<Batch>(3)
        private val full = ArrayBlockingQueue<Batch>(3)
        private val synced = ArrayBlockingQueue<Any>(1)
        private var current = Batch(DoubleArray(Batch.ROWS * Batch.STRIDE))

        @Volatile
        private var failure: Throwable? = null
        private var reported = false
        private val thread = Thread(::loop, "replay-csv-writer").apply { isDaemon = true }

        init {
            repeat(2) { free.add(Batch(DoubleArray(Batch.ROWS * Batch.STRIDE))) }
            thread.start()
        }

        fun add(step: ReplayStep) {
            val b = current
            val d = b.data
            val i = b.count * Batch.STRIDE
            d[i] = step.timeS
            step.orientation.copyInto(d, i + 1, 0, 4)
            step.specificForce.copyInto(d, i + 5, 0, 3)
            if (++b.count == Batch.ROWS) handOver()
        }

        /** Throws the thread's failure, once (a close after a failed step does not throw it again). */
        private fun rethrow() {
            val f = failure ?: return
            if (reported) return
            reported = true
            throw f
        }

        private fun handOver() {
            rethrow()
            full.put(current)
            current = free.take()
            current.count = 0
        }

        /** Hands over what is pending and a [marker]; returns when the thread has written (and flushed) it all. */
        fun sync(marker: Int) {
            if (!thread.isAlive) return rethrow()
            full.put(current)
            full.put(Batch(DoubleArray(0)).also { it.count = marker })
            synced.take()
            if (marker == Batch.END) thread.join() else current = free.take().also { it.count = 0 }
            rethrow()
        }

        private fun loop() {
            while (true) {
                val b = full.take()
                try {
                    if (failure == null) {
                        when (b.count) {
                            Batch.FLUSH, Batch.END -> { drain(); out.flush() }
                            else -> for (r in 0 until b.count) {
                                val o = r * Batch.STRIDE
                                format(b.data[o], b.data, o + 1, b.data, o + 5)
                            }
                        }
                    }
                } catch (e: Throwable) {
                    failure = e
                }
                when (b.count) {
                    Batch.FLUSH -> synced.put(Unit)
                    Batch.END -> { synced.put(Unit); return }
                    else -> free.put(b)
                }
            }
        }
    }

    public companion object {
        public const val HEADER: String = "t_s,qw,qx,qy,qz,azimuth_deg,pitch_deg,roll_deg,yaw_deg,aero_pitch_deg,aero_roll_deg," +
            "lin_acc_east_m_s2,lin_acc_north_m_s2,lin_acc_up_m_s2"
        private const val COMMA = ','.code.toByte()
        private const val NL = '\n'.code.toByte()
        private const val MINUS = '-'.code.toByte()
        private const val ZERO = '0'.code.toByte()
        private const val N = 'N'.code.toByte()
        private const val MAX_ROW = 14 * 48
        private const val DEG = 180.0 / Math.PI

        /**
         * From the unit quaternion [q] (sensor → ENU) and the specific force [a] (device frame):
         * out[0..2] Android azimuth, pitch, roll; out[3..5] aerospace yaw, pitch, roll (degrees,
         * conventions in the file header); out[6..8] ENU linear acceleration (m/s²).
         */
        @JvmStatic
        public fun derived(q: DoubleArray, a: DoubleArray, out: DoubleArray): Unit = derived(q, 0, a, 0, out)

        private fun derived(q: DoubleArray, qAt: Int, a: DoubleArray, aAt: Int, out: DoubleArray) {
            Orientations.androidAndAerospaceAngles(q, qAt, out, 0)
            for (k in 0 until 6) out[k] *= DEG
            val ax = a[aAt]
            val ay = a[aAt + 1]
            val az = a[aAt + 2]
            unitQuaternionToMatrix(q, qAt) { r00, r01, r02, r10, r11, r12, r20, r21, r22 ->
                out[6] = r00 * ax + r01 * ay + r02 * az
                out[7] = r10 * ax + r11 * ay + r12 * az
                out[8] = r20 * ax + r21 * ay + r22 * az - STANDARD_GRAVITY
            }
        }
    }
}
