package dev.motionfusion.app.sessions

import android.content.Intent
import android.system.ErrnoException
import android.system.OsConstants
import android.widget.Button
import android.widget.TextView
import androidx.appcompat.app.AlertDialog
import dev.motionfusion.app.R
import dev.motionfusion.app.TestGraph
import dev.motionfusion.app.offMainThread
import dev.motionfusion.app.platform.Failure
import java.io.IOException
import org.junit.Assert.assertEquals
import org.junit.Assert.assertTrue
import org.junit.Before
import org.junit.Test
import org.junit.runner.RunWith
import org.robolectric.Robolectric
import org.robolectric.RobolectricTestRunner
import org.robolectric.RuntimeEnvironment
import org.robolectric.annotation.Config
import org.robolectric.shadows.ShadowDialog
import org.robolectric.shadows.ShadowLog

/**
 * A failed action on a session says what kind of failure it was in the user's language; the
 * exception's own (English) words go to the log, never to the screen.
 */
@RunWith(RobolectricTestRunner::class)
class FailureTextTest {
    private val app = RuntimeEnvironment.getApplication()
    private lateinit var graph: TestGraph

    @Before
    fun setUp() {
        graph = TestGraph()
    }

    @Test
    @Config(qualifiers = "de")
    fun `in German, a session being recorded is not deleted nor renamed and an unreadable one not shared, each said in German`() {
        // A session that is being recorded (its folder made, nothing written yet).
        val dir = offMainThread { graph.graph.sessions.newRecording(1_795_684_500_000L) }
        val intent = Intent(app, SessionDetailActivity::class.java).putExtra(SessionDetailActivity.EXTRA_SESSION, dir.name)
        val a = Robolectric.buildActivity(SessionDetailActivity::class.java, intent).setup().get()
        graph.settle()
        val message = { a.findViewById<TextView>(R.id.detail_message).text.toString() }

        a.findViewById<Button>(R.id.detail_share).performClick()
        graph.settle()
        assertEquals("Export fehlgeschlagen: die Dateien der Sitzung sind nicht lesbar: sie sind vielleicht beschädigt (die Sitzungsliste nennt die fehlerhafte Datei)", message())

        a.findViewById<Button>(R.id.detail_delete).performClick()
        (ShadowDialog.getLatestDialog() as AlertDialog).getButton(AlertDialog.BUTTON_POSITIVE).performClick()
        graph.settle()
        assertEquals("Nicht gelöscht: die Sitzung wird gerade aufgenommen: zuerst die Aufnahme beenden", message())
        assertTrue("kept", offMainThread { dir.isDirectory })
        // Renamed while it is being recorded: that is said, not that the name is wrong.
        a.rename("Morgenrunde")
        graph.settle()
        assertEquals("Nicht umbenannt: die Sitzung wird gerade aufgenommen: zuerst die Aufnahme beenden", message())
        // The system's words are in the log.
        assertTrue(ShadowLog.getLogsForTag("Failure").any { it.throwable?.message == "the session is being recorded" })
    }

    @Test
    fun `each failure is recognised by its kind, through wrapping exceptions`() {
        val full = IOException("write failed", ErrnoException("write", OsConstants.ENOSPC))
        assertEquals(Failure.STORAGE_FULL, Failure.of(full, "test"))
        assertEquals(Failure.NO_APP, Failure.of(android.content.ActivityNotFoundException("No Activity found"), "test"))
        assertEquals(Failure.STORAGE, Failure.of(IOException("Input/output error"), "test"))
        for (f in Failure.entries) assertTrue(f.name, app.getString(f.text).isNotBlank())
    }
}
