package dev.motionfusion.app.sensor

import dev.motionfusion.core.event.SessionStream

/**
 * Puts sensor events back in timestamp order. Android delivers each sensor's events in order,
 * but the sensors' batches separately, so the merged stream steps back by up to a batch (a few ms
 * without hardware batching, up to the report latency with it). The window keeps one queue per
 * stream, each in order, and holds events until a later one [windowNs] (sensor time) newer has
 * arrived; it then releases them merged across the queues in the order of fusion-core's session
 * reader: by timestamp, and at equal timestamps by [SessionStream] order (accelerometer and
 * magnetometer before the gyroscope), so that a recording replayed by `fusion replay` feeds the
 * filter exactly the sequence it saw live. A batch of seconds of one sensor after another's costs
 * an append per event and a look at each stream's oldest per release, not a move per waiting event.
 *
 * An event older than one already released cannot be put in order: it is released at once and
 * counted in [late]. A full queue releases the oldest waiting event early until it has room.
 * Primitive slots, allocated for a stream at its first event and when [ensureCapacity] grows them,
 * never per event; one thread (the capture consumer).
 */
internal class ReorderWindow(capacity: Int = DEFAULT_CAPACITY, windowNs: Long = DEFAULT_WINDOW_NS) {
    init {
        require(capacity >= 2) { "capacity must be ≥ 2, was $capacity" }
        require(windowNs >= 0) { "window must be ≥ 0 ns, was $windowNs" }
    }

    /** Events each stream's queue holds. */
    var capacity: Int = capacity
        private set

    /** How long (sensor time) an event is held for older ones of other streams to arrive; any value ≥ 0 at any time. */
    var windowNs: Long = windowNs
        set(value) {
            require(value >= 0) { "window must be ≥ 0 ns, was $value" }
            field = value
        }

    private val stride = SensorStreams.maxValues
    private val queues = arrayOfNulls<Queue>(SessionStream.entries.size)

    /** The ordinals that have a queue, ascending: the streams looked at for the oldest event. */
    private var active = IntArray(0)
    private var count = 0
    private var newestNs = Long.MIN_VALUE
    private var releasedNs = Long.MIN_VALUE
    private var releasedOrdinal = -1

    /** Events that arrived after a later one had been released (passed on out of order). */
    var late: Long = 0L
        private set

    /** Events waiting. */
    val size: Int get() = count

    /** Grows every stream's queue to hold at least [perStream] events, keeping those waiting; allocates only when it grows. */
    fun ensureCapacity(perStream: Int) {
        if (perStream <= capacity) return
        capacity = perStream
        for (q in queues) q?.grow(perStream)
    }

    /** Adds one event ([values] at [offset], [SensorStreams.maxValues] floats) and releases what is due to [sink]. */
    fun add(stream: SessionStream, timestampNs: Long, accuracy: Int, values: FloatArray, offset: Int, afterGap: Boolean, sink: EventRing.Consumer) {
        val ord = stream.ordinal
        val q = queues[ord] ?: Queue(capacity).also {
            queues[ord] = it
            active = (active + ord).sortedArray()
        }
        while (q.count == capacity) releaseOne(sink)
        if (timestampNs < releasedNs || (timestampNs == releasedNs && ord < releasedOrdinal)) {
            late++
            sink.event(stream, timestampNs, accuracy, values, offset, afterGap)
            return
        }
        q.insert(timestampNs, (if (afterGap) GAP else 0) or (accuracy and 0xff), values, offset)
        count++
        if (timestampNs > newestNs) newestNs = timestampNs
        val due = newestNs - windowNs
        while (count > 0) {
            val o = oldest()
            if (queues[o]!!.headTime() > due) break
            release(o, sink)
        }
    }

    /** Releases everything waiting, in order (the sensors stopped, or went quiet). */
    fun flush(sink: EventRing.Consumer) {
        while (count > 0) releaseOne(sink)
    }

    /** Forgets everything waiting and the order seen so far (a new registration). */
    fun clear() {
        for (q in queues) q?.let { it.start = 0; it.count = 0 }
        count = 0; newestNs = Long.MIN_VALUE; releasedNs = Long.MIN_VALUE; releasedOrdinal = -1
    }

    /** The ordinal of the stream whose first waiting event comes first (timestamp, then stream order). */
    private fun oldest(): Int {
        var best = -1
        var bestT = Long.MAX_VALUE
        val a = active
        for (i in a.indices) {
            val o = a[i]
            val q = queues[o]!!
            if (q.count == 0) continue
            val t = q.headTime()
            if (best < 0 || t < bestT) { best = o; bestT = t }
        }
        return best
    }

    private fun releaseOne(sink: EventRing.Consumer) = release(oldest(), sink)

    private fun release(ord: Int, sink: EventRing.Consumer) {
        val q = queues[ord]!!
        val s = q.start
        q.start = if (s + 1 == q.times.size) 0 else s + 1
        q.count--
        count--
        val m = q.meta[s]
        releasedNs = q.times[s]
        releasedOrdinal = ord
        sink.event(SensorStreams.ofOrdinal(ord), q.times[s], m.toByte().toInt(), q.values, s * stride, m and GAP != 0)
    }

    /** One stream's waiting events in timestamp order: a ring of primitive slots. */
    private inner class Queue(capacity: Int) {
        var times = LongArray(capacity)
        var meta = IntArray(capacity) // gap << 30 | accuracy
        var values = FloatArray(capacity * stride)
        var start = 0
        var count = 0

        fun headTime(): Long = times[start]

        private fun slot(i: Int): Int {
            val k = start + i
            return if (k >= times.size) k - times.size else k
        }

        /** Appends; an event older than the newest waiting one of its stream (Android keeps each stream in order, so rarely) is inserted from the end. */
        fun insert(t: Long, m: Int, src: FloatArray, offset: Int) {
            var j = count
            while (j > 0) {
                val prev = slot(j - 1)
                if (times[prev] <= t) break
                val to = slot(j)
                times[to] = times[prev]
                meta[to] = meta[prev]
                System.arraycopy(values, prev * stride, values, to * stride, stride)
                j--
            }
            val s = slot(j)
            times[s] = t
            meta[s] = m
            System.arraycopy(src, offset, values, s * stride, stride)
            count++
        }

        fun grow(n: Int) {
            val t = LongArray(n)
            val m = IntArray(n)
            val v = FloatArray(n * stride)
            for (i in 0 until count) {
                val s = slot(i)
                t[i] = times[s]
                m[i] = meta[s]
                System.arraycopy(values, s * stride, v, i * stride, stride)
            }
            times = t; meta = m; values = v; start = 0
        }
    }

    companion object {
        /** 30 ms: longer than the batches Android hands over at once at 100–500 Hz without hardware batching, shorter than two frames. */
        const val DEFAULT_WINDOW_NS = 30_000_000L

        /** Events per stream's queue before [ensureCapacity]: 1024, 30 ms at 34 kHz. */
        const val DEFAULT_CAPACITY = 1024

        private const val GAP = 1 shl 30
    }
}
