package dev.motionfusion.app.sensor

import dev.motionfusion.core.event.SessionStream

/**
 * Puts sensor events back in timestamp order. Android delivers each sensor's events in order,
 * but the sensors' batches separately, so the merged stream steps back by up to a batch. The
 * window holds events until a later one [windowNs] (sensor time) newer has arrived, then releases
 * them in the order of fusion-core's session reader: by timestamp, and at equal timestamps by
 * [SessionStream] order (accelerometer and magnetometer before the gyroscope), so that a
 * recording replayed by `fusion replay` feeds the filter exactly the sequence it saw live.
 *
 * An event older than one already released cannot be put in order: it is released at once and
 * counted in [late]. A full window releases its oldest event early. Primitive slots, no
 * allocation per event; one thread (the capture consumer).
 */
internal class ReorderWindow(val capacity: Int = 4096, private val windowNs: Long = DEFAULT_WINDOW_NS) {
    init {
        require(capacity >= 2) { "capacity must be ≥ 2, was $capacity" }
        require(windowNs >= 0) { "window must be ≥ 0 ns, was $windowNs" }
    }

    private val stride = SensorStreams.maxValues
    private val times = LongArray(capacity)
    private val meta = IntArray(capacity) // gap << 30 | ordinal << 8 | accuracy
    private val values = FloatArray(capacity * stride)
    private var start = 0
    private var count = 0
    private var newestNs = Long.MIN_VALUE
    private var releasedNs = Long.MIN_VALUE
    private var releasedOrdinal = -1

    /** Events that arrived after a later one had been released (passed on out of order). */
    var late: Long = 0L
        private set

    /** Events waiting. */
    val size: Int get() = count

    /** Adds one event ([values] at [offset], [SensorStreams.maxValues] floats) and releases what is due to [sink]. */
    fun add(stream: SessionStream, timestampNs: Long, accuracy: Int, values: FloatArray, offset: Int, afterGap: Boolean, sink: EventRing.Consumer) {
        val ord = stream.ordinal
        if (timestampNs < releasedNs || (timestampNs == releasedNs && ord < releasedOrdinal)) {
            late++
            sink.event(stream, timestampNs, accuracy, values, offset, afterGap)
            return
        }
        if (count == capacity) releaseOne(sink)
        // Insertion from the end: events arrive nearly in order, so few slots move.
        var j = count
        while (j > 0) {
            val prev = slot(j - 1)
            val pt = times[prev]
            if (pt < timestampNs || (pt == timestampNs && (meta[prev] ushr 8 and 0xff) <= ord)) break
            move(prev, slot(j))
            j--
        }
        val s = slot(j)
        times[s] = timestampNs
        meta[s] = (if (afterGap) GAP else 0) or (ord shl 8) or (accuracy and 0xff)
        System.arraycopy(values, offset, this.values, s * stride, stride)
        count++
        if (timestampNs > newestNs) newestNs = timestampNs
        val due = newestNs - windowNs
        while (count > 0 && times[start] <= due) releaseOne(sink)
    }

    /** Releases everything waiting, in order (the sensors stopped, or went quiet). */
    fun flush(sink: EventRing.Consumer) {
        while (count > 0) releaseOne(sink)
    }

    /** Forgets everything waiting and the order seen so far (a new registration). */
    fun clear() {
        count = 0; start = 0; newestNs = Long.MIN_VALUE; releasedNs = Long.MIN_VALUE; releasedOrdinal = -1
    }

    private fun releaseOne(sink: EventRing.Consumer) {
        val s = start
        start = if (start + 1 == capacity) 0 else start + 1
        count--
        val m = meta[s]
        val ord = m ushr 8 and 0xff
        releasedNs = times[s]
        releasedOrdinal = ord
        sink.event(SensorStreams.ofOrdinal(ord), times[s], m.toByte().toInt(), values, s * stride, m and GAP != 0)
    }

    private fun slot(i: Int): Int {
        val k = start + i
        return if (k >= capacity) k - capacity else k
    }

    private fun move(from: Int, to: Int) {
        times[to] = times[from]
        meta[to] = meta[from]
        System.arraycopy(values, from * stride, values, to * stride, stride)
    }

    companion object {
        /** 30 ms: longer than the batches Android hands over at once at 100–500 Hz, shorter than two frames. */
        const val DEFAULT_WINDOW_NS = 30_000_000L
        private const val GAP = 1 shl 30
    }
}
