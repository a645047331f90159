package dev.motionfusion.app.stream

import android.os.Looper
import dev.motionfusion.app.TestGraph
import dev.motionfusion.core.stream.StreamMessage
import dev.motionfusion.stream.StreamClient
import java.util.concurrent.TimeUnit
import org.robolectric.Shadows.shadowOf

/**
 * Connects [client] to the graph's stream on a thread of its own and allows it once the controller shows it asking (the
 * server's thread asks through the main looper, which this runs); returns its hello.
 */
internal fun TestGraph.connectAllowed(client: StreamClient): StreamMessage.Hello {
    val controller = graph.stream
    val pool = java.util.concurrent.Executors.newSingleThreadExecutor()
    try {
        val hello = pool.submit<StreamMessage.Hello> { client.connect() }
        for (k in 0 until 10_000) {
            shadowOf(Looper.getMainLooper()).idle()
            val asking = (controller.state.value as? StreamState.On)?.clients?.firstOrNull { it.awaitingConfirmation }
            if (asking != null) {
                controller.allow(asking.id)
                settle()
                break
            }
            java.util.concurrent.locks.LockSupport.parkNanos(1_000_000)
        }
        return hello.get(10, TimeUnit.SECONDS)
    } finally {
        pool.shutdown()
    }
}
