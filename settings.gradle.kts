// Android Studio project (Gradle). The build of record is the Maven reactor (pom.xml); these files
// describe the same modules, folders, dependencies, versions, test properties and JVM flags, and
// AndroidStudioProjectTest (app) fails when the two differ. The Gradle build runs on a CI with
// network access (.github/workflows/gradle.yml); the machines of the Maven build reach no Gradle
// distribution and no Android Gradle Plugin.
pluginManagement {
    repositories {
        google {
            content {
                includeGroupByRegex("com\\.android.*")
                includeGroupByRegex("com\\.google.*")
                includeGroupByRegex("androidx.*")
            }
        }
        mavenCentral()
        gradlePluginPortal()
    }
}

plugins {
    // Downloads the JDK of jvmToolchain(17) where the machine has another one (Android Studio's bundled JDK 21).
    id("org.gradle.toolchains.foojay-resolver-convention") version "0.9.0"
}

dependencyResolutionManagement {
    repositoriesMode.set(RepositoriesMode.FAIL_ON_PROJECT_REPOS)
    repositories {
        google()
        mavenCentral()
    }
}

rootProject.name = "motion-fusion"

// fusion-bench (JMH) depends on the app module's recording classes, which Gradle does not offer to
// a JVM module: run it with Maven. android-libs and android-test-libs are the Maven build's way of
// resolving AARs; Gradle resolves them itself from the app's dependencies.
include(":fusion-core")
include(":fusion-stream")
include(":fusion-cli")
include(":app")
