package dev.motionfusion.app.platform

import dev.motionfusion.app.record.RecordingService
import dev.motionfusion.app.stream.StreamService
import org.junit.Assert.assertEquals
import org.junit.Test

/**
 * Every notification the app posts has an id of its own: a stream started while a recording waits for its
 * "tap to continue" must not replace that offer (nor the recording's end alert).
 */
class NotificationIdsTest {
    @Test
    fun `the services' notification ids are distinct`() {
        val ids = listOf(
            RecordingService.NOTIFICATION_ID,
            RecordingService.END_NOTIFICATION_ID,
            RecordingService.INTERRUPTED_NOTIFICATION_ID,
            StreamService.NOTIFICATION_ID,
        )
        assertEquals(ids.toString(), ids.size, ids.toSet().size)
    }
}
