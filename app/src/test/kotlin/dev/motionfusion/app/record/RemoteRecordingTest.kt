package dev.motionfusion.app.record

import dev.motionfusion.app.live.TestCapture
import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.session.ClockAnchor
import dev.motionfusion.core.session.RemoteStart
import dev.motionfusion.core.session.SessionMetadata
import dev.motionfusion.core.session.SessionReader
import dev.motionfusion.core.session.SessionWriter
import dev.motionfusion.core.sync.ClockExchange
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.io.TempDir
import java.nio.file.Path

/**
 * A recording a laptop started (docs/STREAMING.md, "Remote control"): no sample before the laptop's instant, its tag in
 * meta.json, and the link's clock exchanges in clock.csv through the session's one writer.
 */
class RemoteRecordingTest {
    @TempDir lateinit var tmp: Path
    private val c = TestCapture()

    @Test
    fun `a remote start keeps no sample before its instant, and the exchanges of the laptop go into clock csv`() {
        val dir = tmp.resolve("s")
        val start = RemoteStart("fusion record on lab", "lab boot 1", 9_000_000_000L, 200_000_000L)
        val sink = CoreSessionSink(SessionWriter.create(dir, SessionMetadata(startAnchor = ClockAnchor(1_764_000_000_000L, 0L), remoteStart = start)))
        val r = Recorder(sink, onEnd = {}, notBeforeNs = start.elapsedRealtimeNs)
        c.record(r)
        val exchanges = listOf(ClockExchange(8_900_000_000L, 100_000_100L, 100_000_200L, 8_900_000_400L), ClockExchange(9_150_000_000L, 350_000_100L, 350_000_150L, 9_150_000_300L))
        for (i in 0 until 500) {
            c.offer(SessionStream.GYROSCOPE, i * 1_000_000L, 0.1f, 0f, 0f)
            if (i == 100) r.clockExchange(exchanges[0], "lab boot 1")
            // Another laptop's exchanges are not this session's link.
            if (i == 200) r.clockExchange(ClockExchange(1, 2, 3, 4), "other boot 2")
            if (i == 350) r.clockExchange(exchanges[1], "lab boot 1")
            if (i % 50 == 0) c.drain()
        }
        c.drain()
        c.stop(r)
        SessionReader.open(dir).use { s ->
            val times = s.events(setOf(SessionStream.GYROSCOPE)).use { e -> val t = ArrayList<Long>(); while (e.next()) t += e.timestampNs; t }
            assertEquals(200_000_000L, times.first())
            assertEquals(300, times.size)
            assertEquals(start, s.metadata.remoteStart)
            assertEquals("lab boot 1", s.metadata.clockLink)
            assertEquals(exchanges, s.clockExchanges())
        }
    }
}
