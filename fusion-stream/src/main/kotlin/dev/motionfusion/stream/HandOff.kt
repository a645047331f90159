package dev.motionfusion.stream

import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.stream.StreamMessage
import java.util.concurrent.ArrayBlockingQueue
import java.util.concurrent.TimeUnit
import java.util.concurrent.atomic.AtomicLong

/**
 * The hand-off from the capture thread to one sender thread, the send loop of both the [StreamServer] and the
 * [UdpPush]: capture never waits for the network. [sample] and [orientation] offer a message to a bounded queue of
 * [capacity] and return at once; a full queue drops it and counts it ([droppedCount]). The sender thread, named
 * [threadName], takes the messages in the order they were offered and gives each, with its sample time, to [send].
 * [stop] ends the sender, waking it while it waits for a message; what is still queued then is not sent.
 */
internal class HandOff(
    capacity: Int,
    threadName: String,
    private val send: (message: StreamMessage, timestampNs: Long) -> Unit,
) {
    private val queue = ArrayBlockingQueue<StreamMessage>(capacity)
    private val dropped = AtomicLong()
    private val sender = Thread(::loop, threadName).apply { isDaemon = true }

    @Volatile private var running = false

    /** Messages offered while the queue was full (none of them sent). */
    val droppedCount: Long get() = dropped.get()

    /** Starts the sender thread. */
    fun start() {
        running = true
        sender.start()
    }

    /** Ends the sender: it sends nothing more, and wakes if it waits. Does not wait for it ([awaitStopped]). */
    fun stop() {
        running = false
        sender.interrupt()
    }

    /** Waits at most [timeoutMs] for the sender to end after [stop]; whether it has. */
    fun awaitStopped(timeoutMs: Long): Boolean {
        if (sender.isAlive) TimeUnit.MILLISECONDS.timedJoin(sender, timeoutMs)
        return !sender.isAlive
    }

    /** Hands a sensor sample to the sender; never blocks. [values] is copied. */
    fun sample(stream: SessionStream, timestampNs: Long, values: FloatArray, accuracy: Int) {
        offer(StreamMessage.Sample(stream, timestampNs, values.copyOf(stream.valueCount.coerceAtMost(values.size)), accuracy))
    }

    /** Hands the fused orientation (sensor → ENU, [w, x, y, z]) to the sender; never blocks. */
    fun orientation(timestampNs: Long, qw: Double, qx: Double, qy: Double, qz: Double) {
        offer(StreamMessage.Orientation(timestampNs, qw, qx, qy, qz))
    }

    private fun offer(m: StreamMessage) {
        if (!queue.offer(m)) dropped.incrementAndGet()
    }

    private fun loop() {
        while (running) {
            val m = try {
                queue.take()
            } catch (_: InterruptedException) {
                return
            }
            send(m, if (m is StreamMessage.Sample) m.timestampNs else (m as StreamMessage.Orientation).timestampNs)
        }
    }
}
