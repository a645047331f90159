/*
 * A cursor over sensor events in time order, the common currency of replay: session folders and
 * zips, plain IMU tables, BROAD trials, phyphox and Sensor Logger exports all come out as SensorEvents.
 * Units and frames as in SessionStream (SI, Android device frame, quaternions sensor → ENU).
 */
package dev.motionfusion.core.event

import java.io.Closeable

/**
 * A cursor: call [next] and, while it returns true, read [stream], [timestampNs], [values] and
 * [accuracy]. The values array is reused by the next call: copy what you keep. Memory is
 * constant whatever the length. Malformed input throws
 * [dev.motionfusion.core.io.DataFormatException] naming source, line and column.
 */
public interface SensorEvents : Closeable {
    /** Advances to the next event; false at the end. */
    public fun next(): Boolean

    /** The stream of the current event. */
    public val stream: SessionStream

    /** Timestamp of the current event, ns (SensorEvent.timestamp base). */
    public val timestampNs: Long

    /** Values of the current event: the first [SessionStream.valueCount] entries are meaningful. */
    public val values: DoubleArray

    /** SensorEvent.accuracy (−1…3), or [NO_ACCURACY] for streams without one. */
    public val accuracy: Int

    public companion object {
        public const val NO_ACCURACY: Int = Int.MIN_VALUE
    }
}

/**
 * Events that come in rows, as a plain IMU table's: per [nextRow] one instant with an accelerometer,
 * a gyroscope and, when [hasMagnetometer], a magnetometer sample, the same three events (accelerometer,
 * magnetometer, gyroscope at [timestampNs]) that [next] gives one by one. Replay takes a row as one
 * step instead of three cursor moves; use either [next] or [nextRow] on one cursor, not both.
 */
internal interface RowEvents : SensorEvents {
    val hasMagnetometer: Boolean

    /** gx, gy, gz (rad/s), ax, ay, az (m/s²), mx, my, mz (µT) of the current row. */
    val row: DoubleArray

    /** Advances to the next row; false at the end. */
    fun nextRow(): Boolean
}

/** One stream's events in file order (a single CSV, or one sensor of an export). */
internal interface StreamCursor : Closeable {
    val stream: SessionStream
    val timestampNs: Long
    val values: DoubleArray
    val accuracy: Int
    fun next(): Boolean
}

/**
 * Merges stream cursors by timestamp (each stream assumed in time order; a stream that steps
 * back is passed through in its own order). Ties go to the stream declared first in
 * [SessionStream], so accelerometer and magnetometer precede the gyroscope at equal times.
 */
internal class MergedEvents(cursors: List<StreamCursor>) : SensorEvents {
    private val all = cursors.sortedBy { it.stream.ordinal }.toTypedArray()
    private val live = BooleanArray(all.size)
    private var primed = false
    private var current: StreamCursor? = null
    private var currentIndex = -1

    override val stream: SessionStream get() = current!!.stream
    override val timestampNs: Long get() = current!!.timestampNs
    override val values: DoubleArray get() = current!!.values
    override val accuracy: Int get() = current!!.accuracy

    override fun next(): Boolean {
        if (!primed) {
            primed = true
            for (i in all.indices) live[i] = all[i].next()
        } else if (currentIndex >= 0) {
            live[currentIndex] = all[currentIndex].next()
        }
        var best = -1
        var bestT = Long.MAX_VALUE
        for (i in all.indices) {
            if (live[i] && (best < 0 || all[i].timestampNs < bestT)) {
                best = i
                bestT = all[i].timestampNs
            }
        }
        currentIndex = best
        current = if (best >= 0) all[best] else null
        return best >= 0
    }

    override fun close() {
        var failure: Throwable? = null
        for (c in all) {
            try {
                c.close()
            } catch (e: Throwable) {
                if (failure == null) failure = e else failure.addSuppressed(e)
            }
        }
        if (failure != null) throw failure
    }
}
