package dev.motionfusion.app.record

import dev.motionfusion.app.TestGraph
import dev.motionfusion.app.offMainThread
import dev.motionfusion.app.settings.RecordingLimits
import java.io.File
import org.junit.Assert.assertEquals
import org.junit.Assert.assertFalse
import org.junit.Assert.assertNull
import org.junit.Assert.assertTrue
import org.junit.Test
import org.junit.runner.RunWith
import org.robolectric.RobolectricTestRunner

/**
 * The restart side of a recording on its own (no service): which recording a restart goes on with, its cut-off session
 * repaired and the gap read; what cannot go on is forgotten. On the recording's disk queue, here a thread of the test.
 */
@RunWith(RobolectricTestRunner::class)
class RecordingResumptionTest {
    private val graph = TestGraph(format = LineFormat())
    private val deps = graph.graph
    private val resumption = RecordingResumption(deps)
    private val limits = RecordingLimits(maxDurationS = 600)

    /** A session cut off by a kill: two rows, the second written in part. */
    private fun killedRecording(startedElapsedMs: Long): File = offMainThread {
        val dir = deps.sessions.newRecording(1_764_000_000_000)
        File(dir, "rows.txt").writeText("GYROSCOPE,4000000000,3,0.1\nGYROSCOPE,4005000000,3,0.")
        deps.inProgress.write(RecordingInProgress.Entry(dir.name, still = false, startedWallMs = 1_764_000_000_000, startedElapsedMs = startedElapsedMs, limits = limits))
        dir
    }

    @Test
    fun `a restart resumes the recording that ran, its session repaired, the gap from its last row to now`() {
        val dir = killedRecording(startedElapsedMs = 3_000)
        val r = offMainThread { resumption.resume(resumedNs = 50_000_000_000L) } ?: error("nothing resumed")
        assertEquals(dir.name, r.entry.session)
        assertEquals(limits, r.entry.limits)
        assertEquals(3_000L, r.entry.startedElapsedMs)
        assertEquals(dir.name, r.continues.previousSession)
        assertEquals(4_000_000_000L, r.continues.gapStartElapsedRealtimeNs) // the partial row cut
        assertEquals(50_000_000_000L, r.continues.gapEndElapsedRealtimeNs)
        assertTrue(offMainThread { File(dir, "recovered").isFile })
        assertTrue("kept until the new session replaces it", offMainThread { deps.inProgress.read() } != null)
    }

    @Test
    fun `after a phone restart (the clock began again) nothing resumes and the recording is forgotten`() {
        killedRecording(startedElapsedMs = 3_000)
        assertNull(offMainThread { resumption.resume(resumedNs = 2_000_000_000L) })
        assertNull(offMainThread { deps.inProgress.read() })
    }

    @Test
    fun `a refused restart keeps the recording waiting for the tap, one whose session is gone is forgotten`() {
        val dir = killedRecording(startedElapsedMs = 3_000)
        assertEquals(dir, offMainThread { resumption.waiting(nowNs = 50_000_000_000L) })
        assertFalse("not repaired before the tap", offMainThread { File(dir, "recovered").exists() })
        assertTrue(offMainThread { deps.inProgress.read() } != null)
        offMainThread { dir.deleteRecursively() }
        assertNull(offMainThread { resumption.waiting(nowNs = 50_000_000_000L) })
        assertNull(offMainThread { deps.inProgress.read() })
    }
}
