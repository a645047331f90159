package dev.motionfusion.app.export

import dev.motionfusion.app.platform.Sdks
import org.robolectric.annotation.Config
import dev.motionfusion.app.offMainThread
import android.content.ContentProvider
import android.content.ContentValues
import android.database.Cursor
import android.net.Uri
import android.os.ParcelFileDescriptor
import android.provider.MediaStore
import dev.motionfusion.app.record.CoreSessionFormat
import dev.motionfusion.app.record.RecordingEnd
import dev.motionfusion.core.session.ClockAnchor
import dev.motionfusion.core.session.SessionMetadata
import dev.motionfusion.core.session.SessionReader
import dev.motionfusion.core.event.SessionStream
import org.junit.Assert.assertEquals
import org.junit.Assert.assertTrue
import org.junit.Test
import org.junit.runner.RunWith
import org.robolectric.Robolectric
import org.robolectric.RobolectricTestRunner
import org.robolectric.RuntimeEnvironment
import java.io.File

/**
 * Save to Downloads against a stand-in for MediaStore's provider that keeps what the app asks
 * of it: the insert (pending), the write, the update that publishes, or a delete on failure.
 */
@RunWith(RobolectricTestRunner::class)
/** MediaStore.Downloads exists from API 29; before it the detail screen offers Save as only (SessionsScreensTest). */
@Config(minSdk = 29, maxSdk = Sdks.MAX)
class DownloadsExportTest {
    class FakeMediaStore : ContentProvider() {
        val log = ArrayList<String>()
        var pending: Int? = null
        var name: String? = null
        var relativePath: String? = null
        var failOpen = false
        val file: File by lazy { File(context!!.cacheDir, "fake-media/download.bin").apply { parentFile!!.mkdirs() } }

        override fun onCreate() = true
        override fun insert(uri: Uri, values: ContentValues?): Uri {
            log += "insert $uri"
            pending = values?.getAsInteger(MediaStore.MediaColumns.IS_PENDING)
            name = values?.getAsString(MediaStore.MediaColumns.DISPLAY_NAME)
            relativePath = values?.getAsString(MediaStore.MediaColumns.RELATIVE_PATH)
            return Uri.withAppendedPath(uri, "1")
        }

        override fun openFile(uri: Uri, mode: String): ParcelFileDescriptor {
            log += "open $mode pending=$pending"
            if (failOpen) throw java.io.FileNotFoundException("storage went away")
            return ParcelFileDescriptor.open(file, ParcelFileDescriptor.parseMode(mode))
        }

        override fun update(uri: Uri, values: ContentValues?, selection: String?, selectionArgs: Array<out String>?): Int {
            pending = values?.getAsInteger(MediaStore.MediaColumns.IS_PENDING)
            log += "update pending=$pending"
            return 1
        }

        override fun delete(uri: Uri, selection: String?, selectionArgs: Array<out String>?): Int {
            log += "delete"
            return 1
        }

        override fun query(uri: Uri, p: Array<out String>?, s: String?, a: Array<out String>?, o: String?): Cursor? = null
        override fun getType(uri: Uri): String? = null
    }

    private fun session(name: String, finish: Boolean = true): File = offMainThread {
        val dir = File(File(RuntimeEnvironment.getApplication().filesDir, "sessions"), name)
        val sink = CoreSessionFormat.create(dir, SessionMetadata(appVersion = "0.1.0", startAnchor = ClockAnchor(0, 0)))
        for (i in 0 until 100) sink.raw(SessionStream.GYROSCOPE, 1_000L * i, 3, floatArrayOf(0.1f, 0.2f, 0.3f), 0)
        if (finish) sink.finish(RecordingEnd.Stopped) else sink.flush()
        dir
    }

    @Test
    fun `save to Downloads inserts pending, writes the zip, then publishes it`() {
        val app = RuntimeEnvironment.getApplication()
        val media = Robolectric.setupContentProvider(FakeMediaStore::class.java, MediaStore.AUTHORITY)
        val dir = session("walk")

        assertEquals("walk.zip", offMainThread { Exporter.toDownloads(app, dir) })
        assertEquals("walk.zip", media.name)
        assertEquals("Download", media.relativePath)
        assertEquals(listOf("insert ${MediaStore.Downloads.EXTERNAL_CONTENT_URI}", "open w pending=1", "update pending=0"), media.log)
        val zip = offMainThread { File(app.cacheDir, "check.zip").apply { writeBytes(media.file.readBytes()) } }
        SessionReader.open(zip.toPath()).use { r -> assertEquals(100L, r.metadata.streams.getValue(SessionStream.GYROSCOPE).samples) }
    }

    @Test
    fun `a failed Downloads export removes the pending entry`() {
        val app = RuntimeEnvironment.getApplication()
        val media = Robolectric.setupContentProvider(FakeMediaStore::class.java, MediaStore.AUTHORITY)
        media.failOpen = true
        val dir = session("walk")
        val failure = runCatching { offMainThread { Exporter.toDownloads(app, dir) } }.exceptionOrNull()
        assertTrue("$failure", failure is java.io.IOException)
        assertEquals("delete", media.log.last())
    }

    @Test
    fun `neither a folder that is not a session nor a session being recorded is exported`() {
        val app = RuntimeEnvironment.getApplication()
        val media = Robolectric.setupContentProvider(FakeMediaStore::class.java, MediaStore.AUTHORITY)
        val notASession = offMainThread { File(File(app.filesDir, "sessions"), "empty").apply { mkdirs() } }
        assertTrue(runCatching { offMainThread { Exporter.toDownloads(app, notASession) } }.exceptionOrNull() is java.io.IOException)
        val recording = session("recording", finish = false)
        val e = runCatching { offMainThread { Exporter.writeZip(recording, File(app.cacheDir, "x.zip")) } }.exceptionOrNull()
        assertTrue("$e", e?.message?.contains("still being recorded") == true)
        assertTrue("nothing inserted", media.log.isEmpty())
    }
}
