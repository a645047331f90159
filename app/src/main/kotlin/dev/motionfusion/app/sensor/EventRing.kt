package dev.motionfusion.app.sensor

import java.util.concurrent.locks.LockSupport

import dev.motionfusion.core.event.SessionStream
import java.util.concurrent.atomic.AtomicLong

/**
 * A bounded single-producer single-consumer queue of sensor events kept as primitives, so
 * that the sensor thread hands an event to the consumer thread without allocating, locking or
 * waiting. Memory is fixed at construction: per slot one timestamp, one stream/accuracy int
 * and [SensorStreams.maxValues] floats (36 bytes; 2^17 slots ≈ 4.7 MB).
 *
 * The producer is the one sensor HandlerThread; the consumer is the one capture thread.
 * Publication: the producer writes the slot, then advances [head] with a release store
 * (`lazySet`); the consumer reads [head] (acquire) before reading slots, and advances [tail]
 * after it is done with them, which frees the slots for the producer.
 *
 * A full ring refuses the event (counted in [refused]) and marks the next event it accepts
 * with a gap flag, which the consumer sees as [Consumer.event]'s `afterGap`: a recording then
 * ends before that event and so never has a hole in the middle, while the live screen goes on.
 */
internal class EventRing(capacity: Int) {
    init {
        require(capacity >= 2 && capacity and (capacity - 1) == 0) { "capacity must be a power of two ≥ 2, was $capacity" }
    }

    val capacity: Int = capacity
    private val mask = capacity - 1L
    private val times = LongArray(capacity)
    private val meta = IntArray(capacity)
    private val values = FloatArray(capacity * SensorStreams.maxValues)
    private val head = AtomicLong() // next slot the producer writes
    private val tail = AtomicLong() // next slot the consumer reads
    @Volatile private var closed = false
    private var gap = false // producer only

    /** Producer-side count of offers refused (ring full, or after [close]). */
    @Volatile var refused: Long = 0L
        private set

    /** Events waiting for the consumer. */
    val size: Int get() = (head.get() - tail.get()).toInt()

    /** Events ever accepted. */
    val accepted: Long get() = head.get()

    /**
     * Producer: queues one event, copying [count] values from [src] (the rest of the slot is
     * NaN). Returns false, without waiting, when the ring is full or closed.
     */
    fun offer(stream: SessionStream, timestampNs: Long, accuracy: Int, src: FloatArray, count: Int): Boolean {
        val h = head.get()
        if (closed || h - tail.get() >= capacity) {
            refused++
            gap = true
            return false
        }
        val slot = (h and mask).toInt()
        times[slot] = timestampNs
        meta[slot] = (if (gap) GAP else 0) or (stream.ordinal shl 8) or (accuracy and 0xff)
        gap = false
        val base = slot * SensorStreams.maxValues
        val n = minOf(count, stream.valueCount, src.size)
        System.arraycopy(src, 0, values, base, n)
        for (i in n until SensorStreams.maxValues) values[base + i] = Float.NaN
        // A volatile write, then the volatile read of the sleeper: a consumer that saw the ring empty is woken.
        head.set(h + 1)
        sleeper?.let { sleeper = null; LockSupport.unpark(it) }
        return true
    }

    @Volatile private var sleeper: Thread? = null

    /**
     * Consumer: blocks the calling thread until an event is offered, it is unparked, or [maxNs]
     * pass; returns at once when events are queued. No polling: the producer wakes it.
     */
    fun awaitEvent(maxNs: Long) {
        sleeper = Thread.currentThread()
        if (head.get() == tail.get()) LockSupport.parkNanos(this, maxNs)
        sleeper = null
    }

    /** Refuses all later offers; queued events stay drainable. */
    fun close() {
        closed = true
    }

    /** Receives drained events; [values] is only valid during the call. */
    fun interface Consumer {
        /** [afterGap]: events were refused just before this one. */
        fun event(stream: SessionStream, timestampNs: Long, accuracy: Int, values: FloatArray, offset: Int, afterGap: Boolean)
    }

    /**
     * Consumer: hands up to [max] queued events, oldest first, to [consumer] and frees their
     * slots. Returns how many were handed over. If [consumer] throws, the event it threw on
     * and the later ones stay queued.
     */
    fun drain(consumer: Consumer, max: Int = Int.MAX_VALUE): Int {
        val t = tail.get()
        val available = head.get() - t
        val n = minOf(available, max.toLong()).toInt()
        var i = 0
        try {
            while (i < n) {
                val slot = ((t + i) and mask).toInt()
                val m = meta[slot]
                consumer.event(
                    SensorStreams.ofOrdinal((m ushr 8) and 0xff), times[slot], m.toByte().toInt(),
                    values, slot * SensorStreams.maxValues, m and GAP != 0,
                )
                i++
            }
        } finally {
            tail.lazySet(t + i)
        }
        return i
    }

    private companion object {
        const val GAP = 1 shl 30
    }
}
